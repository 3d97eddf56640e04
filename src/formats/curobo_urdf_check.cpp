// What keeps cuRobo's URDF parser from loading a robot (curobo_urdf_check.h).
#include "medspheres/formats/curobo_urdf_check.h"

#include <string>

#include "number_text.h"

namespace medspheres::formats {

namespace {

// The limits of \p j that cuRobo v2 takes as the empty range [-x, x] (x not positive).
std::string empty_ranges(const Joint& j) {
  std::string out;
  if (!(j.limits->velocity > 0.0)) out = "velocity " + exact_number_text(j.limits->velocity);
  if (!(j.limits->effort > 0.0))
    out += (out.empty() ? "effort " : " and effort ") + exact_number_text(j.limits->effort);
  return out;
}

}  // namespace

std::vector<std::string> curobo_urdf_problems(const RobotModel& model) {
  std::vector<std::string> out;
  for (const Joint& j : model.joints) {
    if (j.type == JointType::kFixed || j.mimic) continue;
    if (!j.limits) {
      if (j.type == JointType::kContinuous)
        out.push_back("continuous joint '" + j.name +
                      "' has no <limit>; cuRobo's URDF parser needs one (effort and velocity) "
                      "to load this robot with any configuration");
      continue;
    }
    const std::string empty = empty_ranges(j);
    if (!empty.empty())
      out.push_back(
          "joint '" + j.name + "' has " + empty +
          " in its <limit>; cuRobo v2's loader takes each as the range [-x, x] and refuses "
          "an empty one, whatever the configuration (v1 loads it); give the joint its "
          "real limits");
  }
  return out;
}

}  // namespace medspheres::formats
