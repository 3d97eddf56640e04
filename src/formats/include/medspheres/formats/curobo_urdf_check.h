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
/// limit or velocity, which cuRobo v1's parser refuses (v2 widens the limit). Also a robot
/// with no actuated joint, for which no XRDF is written (writes_xrdf).
std::vector<std::string> curobo_urdf_problems(const RobotModel& model);

/// False for a robot with no actuated joint (no joint that is neither fixed nor mimic): an
/// XRDF's cspace must list one, since cuRobo's XRDF loaders take the largest of its
/// acceleration limits (v1 util/xrdf_utils.py:128, v2 _src/util/xrdf_util.py:123), and both
/// refuse an XRDF without cspace. So `medspheres robot` writes no XRDF for such a robot (a
/// gripper or a tool on its own); the cuRobo YAML carries its spheres.
bool writes_xrdf(const RobotModel& model);

}  // namespace medspheres::formats
