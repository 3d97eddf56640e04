// Which joints belong to a gripper or a hand (gripper_joints.h).
#include "gripper_joints.h"

#include <string>
#include <utility>

#include "link_tree.h"

namespace medspheres::detail {

namespace {

using Pose = Eigen::Isometry3d;

// The moving joints below link \p l through fixed joints, each with its parent's pose in
// l's frame at the zero pose.
std::vector<std::pair<const Joint*, Pose>> branches_below(const RobotModel& m, const LinkTree& t,
                                                          std::size_t l) {
  std::vector<std::pair<const Joint*, Pose>> out;
  std::vector<std::pair<std::size_t, Pose>> open{{l, Pose::Identity()}};
  while (!open.empty()) {
    const auto [k, X] = open.back();
    open.pop_back();
    for (const Joint* j : t.children[k]) {
      if (j->type == JointType::kFixed)
        open.emplace_back(LinkTree::index(m, j->child), X * j->origin);
      else
        out.emplace_back(j, X);
    }
  }
  return out;
}

// Adds the joints of the branch that starts at joint \p j (its parent's pose in the
// carrier's frame \p X) to \p joints; false when a link of it lies farther than kHandReach
// from the carrier at the zero pose, or a joint of it is continuous and actuated (a wheel; a
// continuous joint that mimics another is a linkage's follower, as some Robotiq 2F
// descriptions type theirs).
bool small_branch(const RobotModel& m, const LinkTree& t, const Joint& j, const Pose& X,
                  std::vector<const Joint*>& joints) {
  std::vector<std::pair<const Joint*, Pose>> open{{&j, X}};
  while (!open.empty()) {
    const auto [k, P] = open.back();
    open.pop_back();
    if (k->type == JointType::kContinuous && !k->mimic) return false;
    const Pose C = P * k->origin;
    if (C.translation().norm() > kHandReach) return false;
    joints.push_back(k);
    for (const Joint* c : t.children[LinkTree::index(m, k->child)]) open.emplace_back(c, C);
  }
  return true;
}

// Marks the joints of the hand that link \p l carries (if it carries one).
void mark_hand(const RobotModel& m, const LinkTree& t, std::size_t l, std::vector<bool>& out) {
  const auto branches = branches_below(m, t, l);
  if (branches.size() < 2) return;
  std::vector<const Joint*> joints;
  for (const auto& [j, X] : branches)
    if (!small_branch(m, t, *j, X, joints)) return;
  for (const Joint* j : joints)
    if (j->type != JointType::kFixed) out[std::size_t(j - m.joints.data())] = true;
}

}  // namespace

std::vector<bool> gripper_joints(const RobotModel& model) {
  std::vector<bool> out(model.joints.size(), false);
  for (std::size_t k = 0; k < model.joints.size(); ++k) {
    const Joint& j = model.joints[k];
    out[k] = j.type != JointType::kFixed && (j.type == JointType::kPrismatic || j.mimic);
  }
  const LinkTree t(model);
  for (std::size_t l = 0; l < model.links.size(); ++l) mark_hand(model, t, l, out);
  return out;
}

}  // namespace medspheres::detail
