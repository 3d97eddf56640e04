// render and view: the mesh or robot on the command line as a render::Scene.
#include "scene_input.h"

#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "cmd_eval_robot.h"
#include "medspheres/error.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/number_text.h"
#include "medspheres/render/render.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_file.h"

namespace medspheres::cli {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

double joint_value(const std::string& text) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v))
    throw InputError("--joints", "\"" + text + "\" is not a finite number");
  return v;
}

// A warning on stderr for each position of \p q outside its joint's limits (a revolute or
// prismatic joint whose URDF gives them): drawn there all the same, but a value in degrees
// or millimetres would show only as an odd picture.
void warn_outside_limits(const RobotModel& model, const std::map<std::string, double>& q) {
  for (const auto& [name, value] : q) {
    const Joint* joint = model.find_joint(name);
    if (!joint || !joint->limits || joint->type == JointType::kContinuous) continue;
    const JointLimits& l = *joint->limits;
    if (l.lower == 0.0 && l.upper == 0.0) continue;  // none given
    if (value < l.lower || value > l.upper)
      std::cerr << "medspheres: warning: --joints: " << name << " = " << number_text(value)
                << " is outside its limits [" << number_text(l.lower) << ", "
                << number_text(l.upper) << "] (radians or metres); drawn there\n";
  }
}

// X_WL of every link at --joints: positions in KinematicTree::joint_names() order, or
// name=value pairs (the others at 0); the zero pose when empty. Positions outside their
// limits are drawn, with a warning.
std::vector<Eigen::Isometry3d> link_poses(const RobotModel& model, const std::string& joints,
                                          const std::string& source) {
  const KinematicTree tree(model, source);
  std::vector<std::string> items;
  std::stringstream in(joints);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  try {
    if (joints.find('=') != std::string::npos) {
      std::map<std::string, double> q;
      for (const std::string& item : items) {
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos || eq == 0)
          throw InputError("--joints", "\"" + item + "\" is not NAME=VALUE");
        q[item.substr(0, eq)] = joint_value(item.substr(eq + 1));
      }
      std::vector<Eigen::Isometry3d> poses = tree.link_poses(q);
      warn_outside_limits(model, q);
      return poses;
    }
    Eigen::VectorXd q = Eigen::VectorXd::Zero(tree.num_positions());
    if (!joints.empty()) {
      if (items.size() != tree.num_positions())
        throw InputError("--joints", "has " + std::to_string(items.size()) +
                                         " values; the robot has " +
                                         std::to_string(tree.num_positions()) + " actuated joints");
      for (std::size_t i = 0; i < items.size(); ++i) q[long(i)] = joint_value(items[i]);
    }
    std::vector<Eigen::Isometry3d> poses = tree.link_poses(q);
    std::map<std::string, double> named;
    for (std::size_t i = 0; i < tree.joint_names().size(); ++i)
      named[tree.joint_names()[i]] = q[long(i)];
    warn_outside_limits(model, named);
    return poses;
  } catch (const std::invalid_argument& e) {
    throw InputError("--joints", e.what());
  }
}

std::map<std::string, LinkSpheres> link_sets(const std::string& path) {
  std::map<std::string, LinkSpheres> out;
  if (ends_with(path, ".robot.json")) {
    for (const Link& link : load_robot(path).links) out[link.name] = link.spheres;
    return out;
  }
  for (auto& [name, set] : read_robot_spheres(path)) out[name].inner = std::move(set);
  return out;
}

SceneInput robot_input(const SceneArgs& args) {
  SceneInput in;
  in.robot = true;
  if (ends_with(args.model, ".robot.json")) {
    if (!args.spheres.empty())
      throw InputError(args.spheres,
                       "a robot file carries its spheres: give the URDF first to "
                       "draw the links' meshes with them");
    const RobotModel model = load_robot(args.model);
    in.source = args.model;
    in.scene = render::robot_scene(model, link_poses(model, args.joints, args.model), {},
                                   link_sets(args.model), args.model);
    return in;
  }
  if (args.spheres.empty())
    throw InputError(args.model, "a URDF needs a robot-level sphere file after it");
  UrdfReadOptions read;
  for (const std::string& p : args.packages) add_package_dir(read.packages, p);
  const UrdfRobot urdf = read_urdf(args.model, read);
  in.source = args.spheres + " over " + args.model;
  in.scene = render::robot_scene(urdf.model, link_poses(urdf.model, args.joints, args.model),
                                 load_link_solids(urdf), link_sets(args.spheres), args.spheres);
  in.mismatch =
      render::mismatch_warning(render::merged_mesh(in.scene),
                               render::merged_spheres(in.scene, render::SetChoice::automatic));
  return in;
}

}  // namespace

void add_scene_options(CLI::App* sub, SceneArgs& args) {
  sub->add_option("model", args.model,
                  "Mesh file (as bake reads it), robot URDF, or robot file (.robot.json)")
      ->required();
  sub->add_option("spheres", args.spheres,
                  "Sphere-set file (.json); after a URDF a robot-level sphere file (robot file, "
                  "cuRobo, XRDF, ...)");
  sub->add_option("--joints", args.joints,
                  "Robot joint positions: q1,q2,... (actuated joints in URDF order) or "
                  "NAME=Q,...; default the zero pose");
  sub->add_option("--package", args.packages, "PKG=DIR: where package://PKG/ meshes live");
}

void check_scene_output(const std::string& output, const SceneArgs& args) {
  try {
    check_output_path(output);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError("-o", e.what());  // an output that cannot be written is bad usage
  }
  check_output_spares_inputs(output, {args.model, args.spheres, args.outer});
}

SceneInput load_scene_input(const SceneArgs& args) {
  if (is_robot_description(args.model) || ends_with(args.model, ".robot.json")) {
    if (!args.outer.empty())
      throw InputError("--outer", "is for a mesh; a robot's sphere file gives its sets");
    SceneInput in = robot_input(args);
    for (const std::string& w : in.scene.warnings)
      std::cerr << "medspheres: warning: " << w << "\n";
    return in;
  }
  if (!args.joints.empty()) throw InputError("--joints", "is for a robot, not a mesh");
  if (args.spheres.empty()) throw InputError(args.model, "a mesh needs a sphere-set file after it");
  const LoadedMesh loaded = load_mesh(args.model);
  for (const std::string& w : loaded.warnings)
    std::cerr << "medspheres: warning: " << args.model << ": " << w << "\n";
  const SphereSet inner = load_sphere_set(args.spheres);
  const SphereSet outer = args.outer.empty() ? SphereSet() : load_sphere_set(args.outer);
  SceneInput in;
  in.source = args.spheres + " over " + args.model;
  in.mismatch = render::mismatch_warning(loaded.mesh, inner);
  if (in.mismatch.empty()) in.mismatch = render::mismatch_warning(loaded.mesh, outer);
  in.scene = render::mesh_scene(loaded.mesh, inner, outer);
  return in;
}

}  // namespace medspheres::cli
