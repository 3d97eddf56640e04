#include "medspheres/formats/xrdf.h"

#include <algorithm>
#include <stdexcept>

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "yaml_spheres.h"

namespace medspheres::formats {

namespace {

void emit_repeated(YAML::Emitter& out, const char* key, double value, std::size_t n) {
  out << YAML::Key << key << YAML::Value;
  emit_yaml_floats(out, std::vector<double>(n, value));
}

// set_base_frame, and add_frame for the placeholder frame (fixed at its parent's origin).
void emit_modifiers(YAML::Emitter& out, const XrdfOptions& options) {
  const PlaceholderFrame& frame = options.placeholder;
  if (options.base_frame.empty() && frame.name.empty()) return;
  out << YAML::Key << "modifiers" << YAML::Value << YAML::BeginSeq;
  if (!options.base_frame.empty())
    out << YAML::BeginMap << YAML::Key << "set_base_frame" << YAML::Value << options.base_frame
        << YAML::EndMap;
  if (!frame.name.empty()) {
    out << YAML::BeginMap << YAML::Key << "add_frame" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "frame_name" << YAML::Value << frame.name;
    out << YAML::Key << "parent_frame_name" << YAML::Value << frame.parent;
    out << YAML::Key << "joint_name" << YAML::Value << frame.joint();
    out << YAML::Key << "joint_type" << YAML::Value << "FIXED";
    out << YAML::Key << "fixed_transform" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "position" << YAML::Value;
    emit_yaml_floats(out, {0.0, 0.0, 0.0});
    out << YAML::Key << "orientation" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "w" << YAML::Value << yaml_float_text(1.0) << YAML::Key << "xyz" << YAML::Value;
    emit_yaml_floats(out, {0.0, 0.0, 0.0});
    out << YAML::EndMap << YAML::EndMap << YAML::EndMap << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

}  // namespace

std::string xrdf_text(const RobotSpheres& spheres, const XrdfOptions& options) {
  validate_robot_spheres(spheres, "XRDF");
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "format" << YAML::Value << "xrdf";
  out << YAML::Key << "format_version" << YAML::Value << yaml_float_text(1.0);
  emit_modifiers(out, options);
  if (!options.joint_names.empty()) {
    out << YAML::Key << "cspace" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "joint_names" << YAML::Value << YAML::Flow << options.joint_names;
    emit_repeated(out, "acceleration_limits", options.acceleration_limit,
                  options.joint_names.size());
    emit_repeated(out, "jerk_limits", options.jerk_limit, options.joint_names.size());
    out << YAML::EndMap;
    std::vector<std::pair<std::string, double>> defaults = options.default_positions;
    if (defaults.empty())
      for (const std::string& j : options.joint_names) defaults.emplace_back(j, 0.0);
    for (const std::string& j : options.joint_names)
      if (std::find_if(defaults.begin(), defaults.end(),
                       [&](const auto& d) { return d.first == j; }) == defaults.end())
        throw std::invalid_argument("xrdf_text: no default position for the joint " + j);
    out << YAML::Key << "default_joint_positions" << YAML::Value << YAML::Flow << YAML::BeginMap;
    for (const auto& [joint, q] : defaults)
      out << YAML::Key << joint << YAML::Value << yaml_float_text(q);
    out << YAML::EndMap;
  }
  if (!options.tool_frames.empty())
    out << YAML::Key << "tool_frames" << YAML::Value << YAML::Flow << options.tool_frames;
  out << YAML::Key << "geometry" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << options.geometry_name << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "spheres" << YAML::Value;
  emit_yaml_link_spheres(out, spheres, options.placeholder);
  out << YAML::EndMap << YAML::EndMap;
  out << YAML::Key << "collision" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "geometry" << YAML::Value << options.geometry_name << YAML::EndMap;
  out << YAML::Key << "self_collision" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "geometry" << YAML::Value << options.geometry_name;
  out << YAML::Key << "ignore" << YAML::Value;
  emit_yaml_link_lists(out, options.self_collision_ignore);
  if (!options.self_collision_buffer.empty()) {
    out << YAML::Key << "buffer_distance" << YAML::Value;
    emit_yaml_number_map(out, options.self_collision_buffer);
  }
  out << YAML::EndMap << YAML::EndMap;
  return yaml_emitter_text(out);
}

RobotSpheres parse_xrdf(const std::string& text, const std::string& source) {
  return read_yaml(text, source, [&](const YAML::Node& doc) {
    if (!doc.IsMap() || !doc["format"] || !doc["format"].IsScalar() ||
        doc["format"].as<std::string>() != "xrdf")
      throw InputError(source, "not an XRDF file: no \"format: xrdf\"");
    const YAML::Node geometry = doc["geometry"];
    if (!geometry || !geometry.IsMap() || geometry.size() == 0)
      throw InputError(source, "no \"geometry\" groups");
    std::string group;
    if (doc["collision"] && doc["collision"]["geometry"]) {
      group = doc["collision"]["geometry"].as<std::string>();
    } else if (geometry.size() == 1) {
      group = geometry.begin()->first.as<std::string>();
    } else {
      throw InputError(source,
                       "several geometry groups and no \"collision: geometry:\" to pick one");
    }
    const YAML::Node g = geometry[group];
    if (!g)
      throw InputError(source, "\"collision\" names the geometry group \"" + group +
                                   "\", which \"geometry\" does not define");
    if (!g["spheres"])
      throw InputError(source, "the geometry group \"" + group + "\" has no \"spheres\"");
    return read_yaml_link_spheres(g["spheres"], source, "geometry: " + group + ": spheres");
  });
}

RobotSpheres load_xrdf(const std::string& path) {
  return parse_xrdf(read_text_file(path), path);
}

void save_xrdf(const std::string& path, const RobotSpheres& spheres, const XrdfOptions& options) {
  validate_robot_spheres(spheres, path);
  write_file_atomically(path, xrdf_text(spheres, options));
}

}  // namespace medspheres::formats
