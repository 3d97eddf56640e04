#include "medspheres/formats/robot_spheres.h"

#include <map>
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

LinkPairLists adjacent_sphere_links(const RobotModel& model, const RobotSpheres& spheres) {
  std::map<std::string, std::string> parent;  // child link -> parent link
  for (const Joint& j : model.joints) parent[j.child] = j.parent;
  std::map<std::string, std::vector<std::string>> below;
  for (const Link& l : model.links) {
    if (!find_link_spheres(spheres, l.name)) continue;
    // Up the tree to the nearest link with spheres (a tree: the walk ends at the root).
    for (auto it = parent.find(l.name); it != parent.end(); it = parent.find(it->second))
      if (find_link_spheres(spheres, it->second)) {
        below[it->second].push_back(l.name);
        break;
      }
  }
  LinkPairLists out;
  for (const Link& l : model.links)
    if (auto it = below.find(l.name); it != below.end()) out.emplace_back(l.name, it->second);
  return out;
}

std::vector<std::string> leaf_links(const RobotModel& model) {
  std::set<std::string> parents;
  for (const Joint& j : model.joints) parents.insert(j.parent);
  std::vector<std::string> out;
  for (const Link& l : model.links)
    if (!parents.count(l.name)) out.push_back(l.name);
  return out;
}

const LinkSphereList* find_link_spheres(const RobotSpheres& spheres, const std::string& link) {
  for (const LinkSphereList& l : spheres)
    if (l.link == link) return &l;
  return nullptr;
}

}  // namespace medspheres::formats
