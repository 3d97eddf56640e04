#include "medspheres/self_pairs.h"

#include "medspheres/error.h"

namespace medspheres {

LinkPair ordered_pair(const std::string& a, const std::string& b) {
  return a < b ? LinkPair{a, b} : LinkPair{b, a};
}

std::set<LinkPair> skipped_self_pairs(const RobotModel& model,
                                      const std::vector<LinkPair>& disabled) {
  std::set<LinkPair> skip;
  for (const Joint& j : model.joints) skip.insert(ordered_pair(j.parent, j.child));
  for (const auto& [a, b] : disabled) {
    for (const std::string* name : {&a, &b})
      if (model.find_link(*name) == nullptr)
        throw InputError(*name, "a disabled collision pair names a link the robot does not have");
    skip.insert(ordered_pair(a, b));
  }
  return skip;
}

}  // namespace medspheres
