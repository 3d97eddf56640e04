#pragma once
// Which joints belong to a gripper or a hand: the planner setup's default tool frames and
// locked joints (planner_setup.cpp). Private to the runtime target.

#include <vector>

#include "medspheres/robot_model.h"

namespace medspheres::detail {

/// The farthest a hand's links lie from the link that carries it, at the zero pose (m):
/// fingers lie within it; a leg, an arm or a second arm does not.
inline constexpr double kHandReach = 0.25;

/// Per joint of \p model (by its index in model.joints), whether it is a gripper's or a
/// hand's joint:
/// - a prismatic or mimic joint (a parallel gripper's jaws, a linkage's followers);
/// - a joint of a hand: a link that carries two or more branches of moving joints (reached
///   through fixed joints), none continuous but those that mimic another (a wheel's is
///   actuated), whose links all lie within kHandReach of it at the zero pose, carries a
///   hand, and every joint of those branches is one (a Jaco's three fingers, an Allegro
///   hand's four, a Robotiq 2F's driver with the joints that mimic it).
/// A fixed joint is none.
std::vector<bool> gripper_joints(const RobotModel& model);

}  // namespace medspheres::detail
