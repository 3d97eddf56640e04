// cuRobo's robot configuration YAML (curobo_yaml.h: the loaders' contract is listed there).
#include "medspheres/formats/curobo_yaml.h"

#include <stdexcept>

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "yaml_spheres.h"

namespace medspheres::formats {

namespace {

std::vector<double> repeated(double value, std::size_t n) {
  return std::vector<double>(n, value);
}

// The cspace mapping: the v2 and v1 names of the default configuration differ.
void emit_cspace(YAML::Emitter& out, const CuroboOptions& o) {
  const std::size_t n = o.joint_names.size();
  std::vector<double> defaults = o.default_positions;
  if (defaults.empty()) defaults = repeated(0.0, n);
  if (defaults.size() != n)
    throw std::invalid_argument("curobo_yaml_text: default_positions and joint_names differ");
  out << YAML::Key << "cspace" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "joint_names" << YAML::Value << YAML::Flow << o.joint_names;
  out << YAML::Key << (o.layout == CuroboLayout::kV1 ? "retract_config" : "default_joint_position")
      << YAML::Value;
  emit_yaml_floats(out, defaults);
  out << YAML::Key << "null_space_weight" << YAML::Value;
  emit_yaml_floats(out, repeated(1.0, n));
  out << YAML::Key << "cspace_distance_weight" << YAML::Value;
  emit_yaml_floats(out, repeated(1.0, n));
  out << YAML::Key << "max_acceleration" << YAML::Value;
  emit_yaml_floats(out, repeated(o.max_acceleration, n));
  out << YAML::Key << "max_jerk" << YAML::Value;
  emit_yaml_floats(out, repeated(o.max_jerk, n));
  out << YAML::EndMap;
}

// The tool frames: v2's list, or v1's primary and the others.
void emit_tool_frames(YAML::Emitter& out, const CuroboOptions& o) {
  if (o.layout == CuroboLayout::kV2) {
    out << YAML::Key << "tool_frames" << YAML::Value << YAML::Flow << o.tool_frames;
    return;
  }
  out << YAML::Key << "ee_link" << YAML::Value << o.tool_frames.front();
  if (o.tool_frames.size() > 1)
    out << YAML::Key << "link_names" << YAML::Value << YAML::Flow << o.tool_frames;
}

// The placeholder frame, fixed at its parent's origin.
void emit_extra_link(YAML::Emitter& out, const PlaceholderFrame& frame) {
  out << YAML::Key << "extra_links" << YAML::Value << YAML::BeginMap << YAML::Key << frame.name
      << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "parent_link_name" << YAML::Value << frame.parent;
  out << YAML::Key << "link_name" << YAML::Value << frame.name;
  out << YAML::Key << "joint_name" << YAML::Value << frame.joint();
  out << YAML::Key << "joint_type" << YAML::Value << "FIXED";
  out << YAML::Key << "fixed_transform" << YAML::Value;
  emit_yaml_floats(out, {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0});
  out << YAML::EndMap << YAML::EndMap;
}

void emit_kinematics(YAML::Emitter& out, const RobotSpheres& spheres, const CuroboOptions& o) {
  out << YAML::BeginMap;
  if (!o.base_link.empty()) out << YAML::Key << "base_link" << YAML::Value << o.base_link;
  if (!o.urdf_path.empty()) out << YAML::Key << "urdf_path" << YAML::Value << o.urdf_path;
  if (!o.tool_frames.empty()) emit_tool_frames(out, o);
  if (!o.placeholder.name.empty()) emit_extra_link(out, o.placeholder);
  out << YAML::Key << "collision_link_names" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const LinkSphereList& l : spheres) out << l.link;
  if (!o.placeholder.name.empty()) out << o.placeholder.name;
  out << YAML::EndSeq << YAML::Key << "collision_spheres" << YAML::Value;
  emit_yaml_link_spheres(out, spheres, o.placeholder);
  out << YAML::Key << "collision_sphere_buffer" << YAML::Value << yaml_float_text(0.0);
  if (!o.tool_frames.empty()) {
    out << YAML::Key << "self_collision_buffer" << YAML::Value;
    emit_yaml_number_map(out, o.self_collision_buffer);
    out << YAML::Key << "self_collision_ignore" << YAML::Value;
    emit_yaml_link_lists(out, o.self_collision_ignore);
    if (!o.lock_joints.empty()) {
      out << YAML::Key << "lock_joints" << YAML::Value;
      emit_yaml_number_map(out, o.lock_joints);
    }
    emit_cspace(out, o);
  } else if (!o.self_collision_ignore.empty()) {
    out << YAML::Key << "self_collision_ignore" << YAML::Value;
    emit_yaml_link_lists(out, o.self_collision_ignore);
  }
  out << YAML::EndMap;
}

}  // namespace

std::string curobo_yaml_text(const RobotSpheres& spheres, const CuroboOptions& options) {
  validate_robot_spheres(spheres, "cuRobo YAML");
  YAML::Emitter out;
  out << YAML::BeginMap;
  if (options.layout == CuroboLayout::kSpheres) {
    out << YAML::Key << "collision_spheres" << YAML::Value;
    emit_yaml_link_spheres(out, spheres);
  } else {
    if (options.layout == CuroboLayout::kV2)
      out << YAML::Key << "format_version" << YAML::Value << yaml_float_text(2.0);
    out << YAML::Key << "robot_cfg" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "kinematics" << YAML::Value;
    emit_kinematics(out, spheres, options);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
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

std::string curobo_yaml_with_urdf_path(const std::string& text,
                                       const std::map<std::string, std::string>& names,
                                       const std::string& source) {
  return read_yaml(text, source, [&](const YAML::Node& doc) {
    const YAML::Node cfg = doc.IsMap() ? doc["robot_cfg"] : YAML::Node();
    const YAML::Node kinematics = cfg && cfg.IsMap() ? cfg["kinematics"] : YAML::Node();
    const YAML::Node path =
        kinematics && kinematics.IsMap() ? kinematics["urdf_path"] : YAML::Node();
    if (!path || !path.IsScalar()) return text;
    const auto it = names.find(path.as<std::string>());
    if (it == names.end()) return text;
    // The scalar as curobo_yaml_text's emitter writes it.
    const auto emitted = [](const std::string& value) {
      YAML::Emitter e;
      e << value;
      return std::string("urdf_path: ") + e.c_str() + "\n";
    };
    const std::string from = emitted(it->first);
    const std::size_t at = text.find(from);
    if (at == std::string::npos) return text;
    return text.substr(0, at) + emitted(it->second) + text.substr(at + from.size());
  });
}

void save_curobo_yaml(const std::string& path, const RobotSpheres& spheres,
                      const CuroboOptions& options) {
  validate_robot_spheres(spheres, path);
  write_file_atomically(path, curobo_yaml_text(spheres, options));
}

}  // namespace medspheres::formats
