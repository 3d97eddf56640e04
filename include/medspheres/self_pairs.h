#pragma once
// The self-collision pairs that a robot's checks leave out: one rule for every checker
// (check::RobotChecker, fcl::RobotBounds).

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "medspheres/robot_model.h"

namespace medspheres {

using LinkPair = std::pair<std::string, std::string>;

/// (a, b) with the smaller name first: the form skipped_self_pairs() stores.
LinkPair ordered_pair(const std::string& a, const std::string& b);

/// The pairs of links that self-collision checks skip: the parent and child links of every
/// joint of \p model (fixed joints included), and the pairs of \p disabled (an SRDF's
/// `<disable_collisions>`, or the pairs a self-collision matrix ignores), each as
/// ordered_pair(). Links joined only through another link are not skipped.
/// \throws InputError naming a link of \p disabled that \p model does not have.
std::set<LinkPair> skipped_self_pairs(const RobotModel& model,
                                      const std::vector<LinkPair>& disabled);

}  // namespace medspheres
