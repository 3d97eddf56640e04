// What keeps cuRobo's URDF parser from loading a robot (curobo_urdf_check.h).
#include "medspheres/formats/curobo_urdf_check.h"

namespace medspheres::formats {

std::vector<std::string> curobo_urdf_problems(const RobotModel& model) {
  std::vector<std::string> out;
  for (const Joint& j : model.joints)
    if (j.type == JointType::kContinuous && !j.limits)
      out.push_back("continuous joint '" + j.name +
                    "' has no <limit>; cuRobo's URDF parser needs one (effort and velocity) to "
                    "load this robot with any configuration");
  return out;
}

}  // namespace medspheres::formats
