#include "mbm_problems.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace medspheres::bench {
namespace {

namespace fs = std::filesystem;

Eigen::Isometry3d pose_of(const YAML::Node& pose) {
  const auto p = pose["position"].as<std::vector<double>>();
  const auto q = pose["orientation"].as<std::vector<double>>();  // x, y, z, w
  if (p.size() != 3 || q.size() != 4) throw std::runtime_error("a pose needs 3 + 4 numbers");
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  x.translate(Eigen::Vector3d(p[0], p[1], p[2]));
  x.rotate(Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized());
  return x;
}

Primitive primitive_of(const YAML::Node& shape, const YAML::Node& pose, bool cylinders_as_boxes) {
  const std::string type = shape["type"].as<std::string>();
  const auto d = shape["dimensions"].as<std::vector<double>>();
  Primitive p;
  p.pose = pose_of(pose);
  if (type == "box" && d.size() == 3) {
    p.kind = Primitive::Kind::box;
    p.half = 0.5 * Eigen::Vector3d(d[0], d[1], d[2]);
  } else if (type == "sphere" && d.size() == 1) {
    p.radius = d[0];
  } else if (type == "cylinder" && d.size() == 2) {  // MoveIt: height, radius
    p.kind = cylinders_as_boxes ? Primitive::Kind::box : Primitive::Kind::capsule;
    p.half = Eigen::Vector3d(d[1], d[1], 0.5 * d[0]);
    p.radius = d[1];
    p.length = d[0];
  } else {
    throw std::runtime_error("a primitive of type '" + type + "' with " + std::to_string(d.size()) +
                             " dimensions");
  }
  return p;
}

PrimitiveScene scene_of(const fs::path& file, bool cylinders_as_boxes) {
  const YAML::Node root = YAML::LoadFile(file.string());
  PrimitiveScene scene{file.stem().string(), {}};
  for (const YAML::Node& object : root["world"]["collision_objects"]) {
    const YAML::Node shapes = object["primitives"], poses = object["primitive_poses"];
    if (shapes.size() != poses.size())
      throw std::runtime_error("object '" + object["id"].as<std::string>("") +
                               "': not as many poses as primitives");
    for (std::size_t i = 0; i < shapes.size(); ++i)
      scene.items.push_back(primitive_of(shapes[i], poses[i], cylinders_as_boxes));
  }
  return scene;
}

std::vector<double> in_order(const std::map<std::string, double>& values,
                             const std::vector<std::string>& joints, const char* what) {
  std::vector<double> out;
  for (const std::string& j : joints) {
    const auto it = values.find(j);
    if (it == values.end()) throw std::runtime_error(std::string(what) + " lacks joint " + j);
    out.push_back(it->second);
  }
  return out;
}

void read_request(const fs::path& file, const std::vector<std::string>& joints, MbmProblem& p) {
  const YAML::Node root = YAML::LoadFile(file.string());
  const YAML::Node state = root["start_state"]["joint_state"];
  const auto names = state["name"].as<std::vector<std::string>>();
  const auto positions = state["position"].as<std::vector<double>>();
  std::map<std::string, double> start, goal;
  for (std::size_t i = 0; i < names.size() && i < positions.size(); ++i)
    start[names[i]] = positions[i];
  for (const YAML::Node& c : root["goal_constraints"][0]["joint_constraints"])
    goal[c["joint_name"].as<std::string>()] = c["position"].as<double>();
  p.start = in_order(start, joints, "the start state");
  p.goal = in_order(goal, joints, "the goal");
}

}  // namespace

std::vector<MbmProblem> load_mbm_problems(const std::string& dir, std::size_t per_set,
                                          const std::vector<std::string>& joints) {
  std::vector<fs::path> sets;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.is_directory()) sets.push_back(e.path());
  std::sort(sets.begin(), sets.end());
  std::vector<MbmProblem> out;
  for (const fs::path& set : sets) {
    std::vector<fs::path> scenes;
    for (const fs::directory_entry& e : fs::directory_iterator(set))
      if (e.path().filename().string().rfind("scene", 0) == 0) scenes.push_back(e.path());
    std::sort(scenes.begin(), scenes.end());
    if (scenes.size() > per_set) scenes.resize(per_set);
    const bool boxes = set.filename().string().rfind("box", 0) == 0;
    for (const fs::path& scene : scenes) {
      MbmProblem p;
      p.set = set.filename().string();
      p.file = scene.string();
      const std::string number = scene.stem().string().substr(5);
      try {
        p.scene = scene_of(scene, boxes);
        read_request(set / ("request" + number + ".yaml"), joints, p);
      } catch (const std::exception& e) {
        throw std::runtime_error(scene.string() + ": " + e.what());
      }
      out.push_back(std::move(p));
    }
  }
  return out;
}

}  // namespace medspheres::bench
