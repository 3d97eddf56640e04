// Loads a medspheres robot file, poses the robot from a joint vector (forward kinematics)
// and asks FCL for the distance from the robot to a box obstacle. Links only
// medspheres::fcl_adapter (the runtime and FCL, no CGAL). The README's tour shows this code.
//
//   robot_distance ROBOT.robot.json CX CY CZ SIDE [q1 q2 ...]
//
// The obstacle is an axis-aligned cube of side SIDE centred on (CX, CY, CZ) in the world
// frame; q lists the actuated joints in tree.joint_names() order (missing ones are 0).
// Prints "distance D" and the actuated joints' names, exit 0; bad input exits 2.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <memory>
#include <vector>

#include <medspheres/error.h>
#include <medspheres/fcl/sphere_set_geometry.h>
#include <medspheres/forward_kinematics.h>
#include <medspheres/robot_file.h>

namespace {

// The robot's distance to the obstacle at joint positions q: the smallest over the links
// of FCL's distance from the link's spheres, posed by forward kinematics.
double robot_distance(const medspheres::RobotModel& robot, const Eigen::VectorXd& q,
                      const fcl::CollisionObjectd& obstacle) {
  // README snippet begins
  const medspheres::KinematicTree tree(robot);
  const std::vector<Eigen::Isometry3d> X_WL = tree.link_poses(q);
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < robot.links.size(); ++i) {
    const medspheres::LinkSpheres& s = robot.links[i].spheres;
    const medspheres::SphereSet& set = s.outer.empty() ? s.inner : s.outer;  // covering first
    if (set.empty()) continue;  // a link without collision geometry
    fcl::CollisionObjectd link(std::make_shared<medspheres::fcl::SphereSetGeometry>(set), X_WL[i]);
    fcl::DistanceRequestd request;
    fcl::DistanceResultd result;
    d = std::min(d, medspheres::fcl::distance(&link, &obstacle, request, result));
  }
  // README snippet ends
  return d;
}

bool parse_number(const char* text, double& value) {
  char* end = nullptr;
  value = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(value);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: robot_distance ROBOT.robot.json CX CY CZ SIDE [q1 q2 ...]\n");
    return 2;
  }
  try {
    const medspheres::RobotModel robot = medspheres::load_robot(argv[1]);
    double c[4];
    for (int k = 0; k < 4; ++k)
      if (!parse_number(argv[2 + k], c[k]) || (k == 3 && c[k] <= 0.0)) {
        std::fprintf(stderr, "robot_distance: bad obstacle number \"%s\"\n", argv[2 + k]);
        return 2;
      }
    const medspheres::KinematicTree tree(robot, argv[1]);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tree.num_positions()));
    if (static_cast<std::size_t>(argc - 6) > tree.num_positions()) {
      std::fprintf(stderr, "robot_distance: %d joint positions for %zu actuated joints\n", argc - 6,
                   tree.num_positions());
      return 2;
    }
    for (int k = 6; k < argc; ++k)
      if (!parse_number(argv[k], q[k - 6])) {
        std::fprintf(stderr, "robot_distance: bad joint position \"%s\"\n", argv[k]);
        return 2;
      }
    fcl::Transform3d X_WO = fcl::Transform3d::Identity();
    X_WO.translation() = fcl::Vector3d(c[0], c[1], c[2]);
    const fcl::CollisionObjectd obstacle(std::make_shared<fcl::Boxd>(c[3], c[3], c[3]), X_WO);
    std::printf("distance %.17g\n", robot_distance(robot, q, obstacle));
    for (const std::string& name : tree.joint_names()) std::printf("joint %s\n", name.c_str());
    return 0;
  } catch (const medspheres::InputError& e) {
    std::fprintf(stderr, "robot_distance: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "robot_distance: %s\n", e.what());
    return 1;
  }
}
