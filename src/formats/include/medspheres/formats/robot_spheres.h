#pragma once
/// \file
/// RobotSpheres: the spheres of a robot per link, the data every robot-level sphere format
/// (cuRobo, XRDF, spherized URDF, SRDF, foam's database) carries. Spheres are in their
/// link's frame, metres.

#include <string>
#include <utility>
#include <vector>

#include "medspheres/robot_model.h"
#include "medspheres/sphere_set.h"

namespace medspheres::formats {

/// The spheres of one link.
struct LinkSphereList {
  std::string link;
  std::vector<Sphere> spheres;
};

/// Links in order (the order a file lists them, or the model's link order). Link names are
/// unique and non-empty.
using RobotSpheres = std::vector<LinkSphereList>;

/// Which set of a RobotModel's links a planner format carries.
enum class SphereChoice {
  kOuter,  ///< the covering set: a planner must not miss a collision (the default)
  kInner,  ///< the inner set
};

/// The chosen set of every link of \p model, in the model's order; links whose chosen set
/// is empty are left out.
RobotSpheres robot_spheres(const RobotModel& model, SphereChoice choice = SphereChoice::kOuter);

/// Checks names (non-empty, unique, no control character) and spheres (validate_sphere_set).
/// \throws InputError "<source>: link "x": ..." naming the link and the problem.
void validate_robot_spheres(const RobotSpheres& spheres, const std::string& source);

/// Link pairs a planner should not test against each other, keyed by one link of each pair:
/// key -> the other links.
using LinkPairLists = std::vector<std::pair<std::string, std::vector<std::string>>>;

/// A frame that cuRobo's files add at the origin of the link \p parent. It carries one
/// sphere of negative radius: cuRobo's disabled sphere, which no check counts (v2's world
/// kernels skip a negative radius, wp_collision_kernel.py:138, and its self-collision
/// kernel masks a pair with one, self_collision_helper.cuh:259; v1's world kernels skip it,
/// sphere_obb_kernel.cu:983, and each self-collision threshold r1 + r2 + buffers stays
/// below zero). cuRobo v2 divides by the number of sphere pairs that it checks, so
/// it refuses a robot whose spheres all sit on one link (ZeroDivisionError,
/// self_collision_params.py:110). The frame gives that robot pairs that never fire. An
/// empty name means no frame.
struct PlaceholderFrame {
  std::string name;
  std::string parent;
  double radius = -1.0;  ///< below minus every other radius and buffer
  /// The fixed joint that holds the frame.
  std::string joint() const { return name + "_joint"; }
};

/// The entry for \p link, or nullptr.
const LinkSphereList* find_link_spheres(const RobotSpheres& spheres, const std::string& link);

}  // namespace medspheres::formats
