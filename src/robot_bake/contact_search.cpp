// A search for a contact that a pair's samples missed (contact_search.h).
#include "contact_search.h"

#include <algorithm>
#include <random>
#include <set>

#include "medspheres/sample_configurations.h"

namespace medspheres::detail {

namespace {

// The joints from link \p link up to the root, by name, nearest first.
std::vector<const Joint*> joints_up(const RobotModel& m, std::string link) {
  std::vector<const Joint*> out;
  for (bool found = true; found;) {
    found = false;
    for (const Joint& j : m.joints)
      if (j.child == link) {
        out.push_back(&j);
        link = j.parent;
        found = true;
        break;
      }
  }
  return out;
}

// The positions (indices into the tree's configuration) that move links a and b apart: the
// actuated joints on the path between them, mimic joints by their sources, locked ones out.
std::vector<std::size_t> path_positions(const RobotModel& m, const KinematicTree& tree,
                                        std::size_t a, std::size_t b,
                                        const std::map<std::string, double>& locked) {
  const auto up_a = joints_up(m, m.links[a].name), up_b = joints_up(m, m.links[b].name);
  const std::set<const Joint*> on_a(up_a.begin(), up_a.end()), on_b(up_b.begin(), up_b.end());
  std::set<std::size_t> out;
  for (const auto* side : {&up_a, &up_b})
    for (const Joint* j : *side) {
      if ((on_a.count(j) && on_b.count(j)) || j->type == JointType::kFixed) continue;
      const std::string name = j->mimic ? j->mimic->joint : j->name;
      const auto& names = tree.joint_names();
      const auto it = std::find(names.begin(), names.end(), name);
      if (it != names.end() && !locked.count(name)) out.insert(std::size_t(it - names.begin()));
    }
  return {out.begin(), out.end()};
}

constexpr int kSteps = 400;         // tries per start
constexpr int kPatience = 12;       // failed tries before the step shrinks
constexpr double kFirst = 0.1;      // the first step, as a share of each joint's range
constexpr double kShrink = 0.6;     // the step's factor after kPatience failures
constexpr double kSmallest = 1e-3;  // the step (share of the range) the climb stops at

}  // namespace

std::optional<Eigen::VectorXd> search_contact(const ContactSearchRobot& r, std::size_t a,
                                              std::size_t b,
                                              const std::vector<Eigen::VectorXd>& starts,
                                              unsigned seed, SolidQueryCounts& counts) {
  const std::vector<std::size_t> moving = path_positions(r.model, r.tree, a, b, r.locked);
  if (moving.empty()) return std::nullopt;
  std::vector<std::pair<double, double>> range;
  for (std::size_t k : moving) range.push_back(sample_range(r.model, r.tree.joint_names()[k]));
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (Eigen::VectorXd q : starts) {
    double best = r.carried.penetration(r.tree.link_poses(q), a, b), step = kFirst;
    for (int t = 0, failed = 0; t < kSteps && step >= kSmallest; ++t) {
      Eigen::VectorXd next = q;
      for (std::size_t i = 0; i < moving.size(); ++i) {
        const auto [lo, hi] = range[i];
        const auto k = static_cast<Eigen::Index>(moving[i]);
        next[k] = std::clamp(q[k] + step * (hi - lo) * normal(rng), lo, hi);
      }
      const std::vector<Eigen::Isometry3d> X = r.tree.link_poses(next);
      const double overlap = r.carried.penetration(X, a, b);
      if (overlap <= best) {
        if (++failed == kPatience) step *= kShrink, failed = 0;
        continue;
      }
      q = next, best = overlap, failed = 0;
      if (r.solids.within(X, a, b, 0.0, &counts)) return q;
    }
  }
  return std::nullopt;
}

}  // namespace medspheres::detail
