#pragma once
// The YAML pieces cuRobo and XRDF share: a mapping from link name to a list of
// {center: [x, y, z], radius: r}, read and written through yaml-cpp.

#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "medspheres/error.h"
#include "medspheres/formats/robot_spheres.h"

namespace medspheres::formats {

/// Parses YAML text. \throws InputError naming \p source and the line on a syntax error.
YAML::Node parse_yaml(const std::string& text, const std::string& source);

/// read(root) on the YAML document \p text. yaml-cpp's own exceptions, from the parse or
/// from reading a node as what it is not (a key looked up in a scalar, a mapping read as
/// text), become InputErrors naming \p source and the line.
template <class Read>
auto read_yaml(const std::string& text, const std::string& source, Read&& read) {
  const YAML::Node root = parse_yaml(text, source);
  try {
    return read(root);
  } catch (const YAML::Exception& e) {
    const std::string line =
        e.mark.is_null() ? "" : " (line " + std::to_string(e.mark.line + 1) + ")";
    throw InputError(source, "unexpected YAML structure" + line + ": " + e.msg);
  }
}

/// Reads a mapping link -> list of {center, radius}, in the file's order, and validates it
/// (validate_robot_spheres). \p where names the mapping ("collision_spheres"). A sphere of
/// finite negative radius is cuRobo's disabled sphere (a placeholder, such as cuRobo's own
/// ur10e.yml puts on tool0, or a PlaceholderFrame's): it is left out, and so is a link left
/// with no sphere.
/// \throws InputError naming \p source, the link, the sphere's index and the problem.
RobotSpheres read_yaml_link_spheres(const YAML::Node& map, const std::string& source,
                                    const std::string& where);

/// \p v as a YAML float that every YAML 1.1 reader (PyYAML, which cuRobo and Isaac use)
/// reads as a float, and reads back to the same double: the shortest exact digits with a
/// '.' in the mantissa and a signed exponent ("0.5", "15.0", "1.0e-05", "-2.5e+20").
/// PyYAML's float pattern needs the '.': it reads "1e-05" as text and "15" as an integer.
std::string yaml_float_text(double v);

/// Writes the mapping link -> list of {center: [x, y, z], radius: r}, each sphere on one
/// line in flow style, numbers as yaml_float_text; then \p placeholder's one sphere at its
/// origin, when it has a name.
void emit_yaml_link_spheres(YAML::Emitter& out, const RobotSpheres& spheres,
                            const PlaceholderFrame& placeholder = {});

/// Writes a mapping link -> [links] (flow lists), `{}` when empty.
void emit_yaml_link_lists(YAML::Emitter& out, const LinkPairLists& lists);

/// Writes a mapping name -> yaml_float_text(value), in \p values' order, `{}` when empty.
void emit_yaml_number_map(YAML::Emitter& out,
                          const std::vector<std::pair<std::string, double>>& values);

/// Writes a flow list of yaml_float_text(value).
void emit_yaml_floats(YAML::Emitter& out, const std::vector<double>& values);

/// The emitter's text, with a final newline. \throws std::logic_error if it failed.
std::string yaml_emitter_text(const YAML::Emitter& out);

}  // namespace medspheres::formats
