#pragma once
/// \file
/// What a user of a robot's planner files should be told once its URDF is read: said by
/// `medspheres robot`, the robot batch and Python's bake_robot alike.

#include <string>
#include <vector>

#include "medspheres/robot/urdf_robot.h"

namespace medspheres {

/// One sentence per warning, without the URDF's name: what keeps cuRobo's URDF parser from
/// loading the robot (formats::curobo_urdf_problems), a floating or planar joint left out
/// with the root link (UrdfRobot::free_base), then, unless \p from_visual, a robot
/// none of whose links has collision geometry (its files would carry no sphere; reading the
/// visual geometry would change that).
std::vector<std::string> robot_warnings(const UrdfRobot& robot, bool from_visual);

}  // namespace medspheres
