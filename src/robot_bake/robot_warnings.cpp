#include "medspheres/robot_bake/robot_warnings.h"

#include <algorithm>

#include "medspheres/formats/curobo_urdf_check.h"

namespace medspheres {

std::vector<std::string> robot_warnings(const UrdfRobot& robot, bool from_visual) {
  std::vector<std::string> out = formats::curobo_urdf_problems(robot.model);
  const bool none = std::all_of(robot.links.begin(), robot.links.end(),
                                [](const UrdfLink& l) { return l.parts.empty(); });
  if (none && !from_visual && !robot.links.empty())
    out.push_back(
        "no link has collision geometry, so the files carry no sphere; --from-visual "
        "(Python: from_visual=True) bakes the visual geometry of such links");
  return out;
}

}  // namespace medspheres
