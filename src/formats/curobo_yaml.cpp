#include "medspheres/formats/curobo_yaml.h"

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "yaml_spheres.h"

namespace medspheres::formats {

std::string curobo_yaml_text(const RobotSpheres& spheres, const CuroboOptions& options) {
  validate_robot_spheres(spheres, "cuRobo YAML");
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "format_version" << YAML::Value << "2.0";
  out << YAML::Key << "robot_cfg" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "kinematics" << YAML::Value << YAML::BeginMap;
  if (!options.base_link.empty())
    out << YAML::Key << "base_link" << YAML::Value << options.base_link;
  out << YAML::Key << "collision_link_names" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const LinkSphereList& l : spheres) out << l.link;
  out << YAML::EndSeq << YAML::Key << "collision_spheres" << YAML::Value;
  emit_yaml_link_spheres(out, spheres);
  out << YAML::Key << "collision_sphere_buffer" << YAML::Value << "0.0";
  if (!options.self_collision_ignore.empty()) {
    out << YAML::Key << "self_collision_ignore" << YAML::Value;
    emit_yaml_link_lists(out, options.self_collision_ignore);
  }
  out << YAML::EndMap << YAML::EndMap << YAML::EndMap;
  return yaml_emitter_text(out);
}

RobotSpheres parse_curobo_yaml(const std::string& text, const std::string& source) {
  return read_yaml(text, source, [&](const YAML::Node& doc) {
    if (!doc.IsMap()) throw InputError(source, "the top level is not a YAML mapping");
    YAML::Node kinematics = doc;
    if (doc["robot_cfg"] && doc["robot_cfg"]["kinematics"])
      kinematics = doc["robot_cfg"]["kinematics"];
    else if (doc["kinematics"])
      kinematics = doc["kinematics"];
    const YAML::Node spheres = kinematics["collision_spheres"];
    if (!spheres)
      throw InputError(source,
                       "no \"collision_spheres\" (looked under robot_cfg: kinematics:, "
                       "under kinematics: and at the top level)");
    if (spheres.IsScalar())
      throw InputError(source, "\"collision_spheres\" names a separate file (\"" +
                                   spheres.as<std::string>() + "\"); convert that file instead");
    return read_yaml_link_spheres(spheres, source, "collision_spheres");
  });
}

RobotSpheres load_curobo_yaml(const std::string& path) {
  return parse_curobo_yaml(read_text_file(path), path);
}

void save_curobo_yaml(const std::string& path, const RobotSpheres& spheres,
                      const CuroboOptions& options) {
  validate_robot_spheres(spheres, path);
  write_file_atomically(path, curobo_yaml_text(spheres, options));
}

}  // namespace medspheres::formats
