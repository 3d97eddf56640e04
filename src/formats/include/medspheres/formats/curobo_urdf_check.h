#pragma once
// What keeps cuRobo's URDF parser from loading a robot, whatever configuration it is given
// (the parser's, not the files medspheres writes): said by `medspheres robot`, the robot
// batch and Python's bake_robot.

#include <string>
#include <vector>

#include "medspheres/robot_model.h"

namespace medspheres::formats {

/// One sentence per problem of \p model's URDF for cuRobo's URDF parser (v1 and v2), naming
/// the joint: URDF allows a continuous joint without <limit>, but the parser reads its effort
/// and velocity and fails before it reads any configuration, cuRobo's own as well; and an
/// actuated joint whose velocity or effort limit is not positive (URDF generators write 0),
/// which cuRobo v2 takes as the empty range [-0, 0] and refuses; and a mimic joint that its
/// source joint, mapped by the multiplier and offset, drives beyond its own lower or upper
/// limit or velocity, which cuRobo v1's parser refuses (v2 widens the limit).
std::vector<std::string> curobo_urdf_problems(const RobotModel& model);

}  // namespace medspheres::formats
