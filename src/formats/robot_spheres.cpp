#include "medspheres/formats/robot_spheres.h"

#include <algorithm>
#include <set>

#include "medspheres/error.h"

namespace medspheres::formats {

RobotSpheres robot_spheres(const RobotModel& model, SphereChoice choice) {
  RobotSpheres out;
  for (const Link& l : model.links) {
    const SphereSet& set = choice == SphereChoice::kOuter ? l.spheres.outer : l.spheres.inner;
    if (!set.empty()) out.push_back({l.name, set.spheres});
  }
  return out;
}

void validate_robot_spheres(const RobotSpheres& spheres, const std::string& source) {
  std::set<std::string> seen;
  for (const LinkSphereList& l : spheres) {
    if (l.link.empty()) throw InputError(source, "a link has an empty name");
    // XML normalises a carriage return, a tab or a line break in an attribute to another
    // character, so such a name would not survive the SRDF and URDF writers' round trip;
    // no URDF means one.
    const auto control = [](unsigned char c) { return c < 0x20 || c == 0x7f; };
    if (std::any_of(l.link.begin(), l.link.end(), control))
      throw InputError(source, "link \"" + l.link + "\" has a control character in its name");
    if (!seen.insert(l.link).second)
      throw InputError(source, "link \"" + l.link + "\" is listed twice");
    SphereSet set;
    set.spheres = l.spheres;
    try {
      validate_sphere_set(set, source);
    } catch (const InputError& e) {
      throw InputError(source, "link \"" + l.link + "\": " + e.problem());
    }
  }
}

const LinkSphereList* find_link_spheres(const RobotSpheres& spheres, const std::string& link) {
  for (const LinkSphereList& l : spheres)
    if (l.link == link) return &l;
  return nullptr;
}

}  // namespace medspheres::formats
