#pragma once
// Private to the fcl_adapter target: the learnt witnesses' points for the kernel's inner
// sets (certified_checker.h, FallbackOptions::kernel_witnesses).

#include <map>
#include <string>
#include <vector>

#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/robot_model.h"

namespace medspheres::fcl::detail {

/// The spheres of \p bounds' witnesses (RobotBounds::witnesses(): inner balls of the
/// sphere trees, or mesh vertices of radius 0, each in its link's frame) by link name, as
/// check::CheckerOptions::inner_points takes them: each is a part of its link's closed
/// solid, so two of them within the margin of each other prove their links colliding,
/// which is what the checker's bounds mode asks of an inner sphere. The kernel then tests
/// every witness point of a link against every inner sphere of the other link of a pair
/// (a witness learnt for one contact can prove another). Each sphere once per link (exact
/// duplicates dropped; sorted, so the same every run). Left out: the links of \p planner
/// without a covering set (their inner set is the spheres mode's, which stays the
/// planner's). Frames: the fallback's links' frames, the planner's (the same robot).
std::map<std::string, std::vector<Sphere>> witness_points(const RobotModel& planner,
                                                          const RobotBounds& bounds);

}  // namespace medspheres::fcl::detail
