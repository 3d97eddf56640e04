#include "yaml_spheres.h"

#include <cmath>
#include <stdexcept>

#include "medspheres/error.h"
#include "number_text.h"

namespace medspheres::formats {

YAML::Node parse_yaml(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source,
                     "not valid YAML (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
}

namespace {

double yaml_number(const YAML::Node& n, const std::string& source, const std::string& where) {
  double v = 0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v))
    throw InputError(source,
                     where + " is not a number (line " + std::to_string(n.Mark().line + 1) + ")");
  return v;
}

Sphere read_sphere(const YAML::Node& e, const std::string& source, const std::string& where) {
  if (!e.IsMap())
    throw InputError(source, where + " is not a mapping {center: [x, y, z], radius: r} (line " +
                                 std::to_string(e.Mark().line + 1) + ")");
  const YAML::Node c = e["center"];
  if (!c || !c.IsSequence() || c.size() != 3)
    throw InputError(source, where + ": \"center\" is not a list of three numbers (line " +
                                 std::to_string(e.Mark().line + 1) + ")");
  const YAML::Node r = e["radius"];
  if (!r) throw InputError(source, where + " has no \"radius\"");
  Sphere s;
  for (std::size_t k = 0; k < 3; ++k)
    s.center[static_cast<Eigen::Index>(k)] = yaml_number(c[k], source, where + " center");
  s.radius = yaml_number(r, source, where + " radius");
  return s;
}

}  // namespace

RobotSpheres read_yaml_link_spheres(const YAML::Node& map, const std::string& source,
                                    const std::string& where) {
  if (!map.IsMap())
    throw InputError(source, "\"" + where + "\" is not a mapping from link names to spheres");
  RobotSpheres out;
  for (const auto& entry : map) {
    LinkSphereList link;
    link.link = entry.first.as<std::string>();
    const YAML::Node& list = entry.second;
    if (list.IsNull()) continue;  // a link listed without spheres
    if (!list.IsSequence())
      throw InputError(source, "link \"" + link.link + "\": the spheres are not a list");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Sphere s =
          read_sphere(list[i], source, "link \"" + link.link + "\" sphere " + std::to_string(i));
      if (!(std::isfinite(s.radius) && s.radius < 0.0)) link.spheres.push_back(s);
    }
    if (!link.spheres.empty()) out.push_back(std::move(link));
  }
  validate_robot_spheres(out, source);
  return out;
}

std::string yaml_float_text(double v) {
  std::string t = exact_number_text(v);
  if (t.find_first_of("in") != std::string::npos)  // inf, nan
    return t[0] == '-' ? "-.inf" : (t[0] == 'n' ? ".nan" : ".inf");
  const std::size_t e = t.find('e');
  std::string mantissa = t.substr(0, e), exponent = e == std::string::npos ? "" : t.substr(e);
  if (mantissa.find('.') == std::string::npos) mantissa += ".0";
  if (!exponent.empty() && exponent[1] != '-' && exponent[1] != '+') exponent.insert(1, "+");
  return mantissa + exponent;
}

namespace {

void emit_link(YAML::Emitter& out, const std::string& link, const std::vector<Sphere>& spheres) {
  out << YAML::Key << link << YAML::Value << YAML::BeginSeq;
  for (const Sphere& s : spheres) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "center" << YAML::Value << YAML::Flow
        << YAML::BeginSeq << yaml_float_text(s.center.x()) << yaml_float_text(s.center.y())
        << yaml_float_text(s.center.z()) << YAML::EndSeq << YAML::Key << "radius" << YAML::Value
        << yaml_float_text(s.radius) << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

}  // namespace

void emit_yaml_link_spheres(YAML::Emitter& out, const RobotSpheres& spheres,
                            const PlaceholderFrame& placeholder) {
  out << YAML::BeginMap;
  for (const LinkSphereList& l : spheres) emit_link(out, l.link, l.spheres);
  if (!placeholder.name.empty())
    emit_link(out, placeholder.name, {Sphere{Eigen::Vector3d::Zero(), placeholder.radius}});
  out << YAML::EndMap;
}

void emit_yaml_link_lists(YAML::Emitter& out, const LinkPairLists& lists) {
  if (lists.empty()) {
    out << YAML::Flow << YAML::BeginMap << YAML::EndMap;
    return;
  }
  out << YAML::BeginMap;
  for (const auto& [link, others] : lists)
    out << YAML::Key << link << YAML::Value << YAML::Flow << others;
  out << YAML::EndMap;
}

void emit_yaml_number_map(YAML::Emitter& out,
                          const std::vector<std::pair<std::string, double>>& values) {
  out << (values.empty() ? YAML::Flow : YAML::Block) << YAML::BeginMap;
  for (const auto& [name, v] : values)
    out << YAML::Key << name << YAML::Value << yaml_float_text(v);
  out << YAML::EndMap;
}

void emit_yaml_floats(YAML::Emitter& out, const std::vector<double>& values) {
  out << YAML::Flow << YAML::BeginSeq;
  for (double v : values) out << yaml_float_text(v);
  out << YAML::EndSeq;
}

std::string yaml_emitter_text(const YAML::Emitter& out) {
  if (!out.good()) throw std::logic_error("YAML emitter: " + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

}  // namespace medspheres::formats
