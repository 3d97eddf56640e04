#pragma once
// A robot's kinematic tree by link index: each link's child joints and its parent joint.
// Private to the runtime target (the planner setup's defaults).

#include <stdexcept>
#include <string>
#include <vector>

#include "medspheres/robot_model.h"

namespace medspheres::detail {

struct LinkTree {
  std::vector<std::vector<const Joint*>> children;
  std::vector<const Joint*> parent;  ///< null at the root

  explicit LinkTree(const RobotModel& m)
      : children(m.links.size()), parent(m.links.size(), nullptr) {
    for (const Joint& j : m.joints) {
      children[index(m, j.parent)].push_back(&j);
      parent[index(m, j.child)] = &j;
    }
  }
  static std::size_t index(const RobotModel& m, const std::string& link) {
    for (std::size_t i = 0; i < m.links.size(); ++i)
      if (m.links[i].name == link) return i;
    throw std::invalid_argument("planner setup: no link \"" + link + "\"");
  }
};

}  // namespace medspheres::detail
