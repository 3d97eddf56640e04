#include "medspheres/robot_bake/robot_warnings.h"

#include <algorithm>

#include "medspheres/formats/curobo_urdf_check.h"

namespace medspheres {

std::vector<std::string> robot_warnings(const UrdfRobot& robot, bool from_visual) {
  std::vector<std::string> out = formats::curobo_urdf_problems(robot.model);
  const FreeBase& free = robot.free_base;
  if (!free.joint.empty())
    out.push_back("the " + free.type + " joint '" + free.joint + "' and the root link '" +
                  free.link + "' it hangs from (no geometry) are left out: the files' base " +
                  "link is '" + robot.model.root_link +
                  "', as planners take a fixed base (the XRDF is cuRobo v2's: v1's XRDF "
                  "loader stops on this joint; give v1 the YAML)");
  const bool none = std::all_of(robot.links.begin(), robot.links.end(),
                                [](const UrdfLink& l) { return l.parts.empty(); });
  if (none && !from_visual && !robot.links.empty())
    out.push_back(
        "no link has collision geometry, so the files carry no sphere; --from-visual "
        "(Python: from_visual=True) bakes the visual geometry of such links");
  return out;
}

}  // namespace medspheres
