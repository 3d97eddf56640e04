#pragma once
// XML through tinyxml2: parsing with errors in medspheres' terms, printing, and reading a
// list of numbers from an attribute.

#include <string>
#include <vector>

#include <tinyxml2.h>

namespace medspheres::formats {

/// Parses \p text into \p doc. \throws InputError naming \p source, the line and tinyxml2's
/// reason when it is not well-formed XML.
void parse_xml(tinyxml2::XMLDocument& doc, const std::string& text, const std::string& source);

/// The root element, which must be named \p name. \throws InputError otherwise.
tinyxml2::XMLElement& xml_root(tinyxml2::XMLDocument& doc, const char* name,
                               const std::string& source);

/// The document's text, indented by tinyxml2's printer.
std::string xml_to_text(const tinyxml2::XMLDocument& doc);

/// The \p count numbers of attribute \p attribute of \p e (\p fallback when absent and
/// \p fallback is not empty). \throws InputError naming \p where and the attribute.
std::vector<double> xml_numbers(const tinyxml2::XMLElement& e, const char* attribute,
                                std::size_t count, const std::vector<double>& fallback,
                                const std::string& source, const std::string& where);

}  // namespace medspheres::formats
