#include "medspheres/formats/robot_spheres.h"

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
