#include "xml_text.h"

#include "medspheres/error.h"
#include "number_text.h"

namespace medspheres::formats {

void parse_xml(tinyxml2::XMLDocument& doc, const std::string& text, const std::string& source) {
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    throw InputError(source, "not well-formed XML (line " + std::to_string(doc.ErrorLineNum()) +
                                 "): " + doc.ErrorStr());
}

tinyxml2::XMLElement& xml_root(tinyxml2::XMLDocument& doc, const char* name,
                               const std::string& source) {
  tinyxml2::XMLElement* root = doc.RootElement();
  if (!root) throw InputError(source, "the XML document has no element");
  if (std::string(root->Name()) != name)
    throw InputError(
        source, std::string("the root element is <") + root->Name() + ">, expected <" + name + ">");
  return *root;
}

std::string xml_to_text(const tinyxml2::XMLDocument& doc) {
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return std::string(printer.CStr(), static_cast<std::size_t>(printer.CStrSize() - 1));
}

std::vector<double> xml_numbers(const tinyxml2::XMLElement& e, const char* attribute,
                                std::size_t count, const std::vector<double>& fallback,
                                const std::string& source, const std::string& where) {
  const char* value = e.Attribute(attribute);
  if (!value) {
    if (!fallback.empty()) return fallback;
    throw InputError(source, where + ": <" + e.Name() + "> has no \"" + attribute +
                                 "\" attribute (line " + std::to_string(e.GetLineNum()) + ")");
  }
  const auto numbers = parse_numbers(value);
  if (!numbers || numbers->size() != count)
    throw InputError(source, where + ": <" + e.Name() + " " + attribute + "=\"" + value +
                                 "\"> is not " + std::to_string(count) + " numbers (line " +
                                 std::to_string(e.GetLineNum()) + ")");
  return *numbers;
}

}  // namespace medspheres::formats
