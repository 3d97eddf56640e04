// A search for a contact that a pair's samples missed (contact_search.h).
#include "contact_search.h"

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <string>

#include "medspheres/sample_configurations.h"

namespace medspheres::detail {

namespace {

// The steps (KinematicTree::steps) from link \p link up to the root, nearest first.
std::vector<std::size_t> steps_up(const KinematicTree& tree, std::size_t link) {
  std::vector<long> into(tree.link_names().size(), -1);  // each link's step, by child
  for (std::size_t k = 0; k < tree.steps().size(); ++k) into[tree.steps()[k].child] = long(k);
  std::vector<std::size_t> out;
  for (long k = into[link]; k >= 0; k = into[tree.steps()[std::size_t(k)].parent])
    out.push_back(std::size_t(k));
  return out;
}

// The positions (indices into the tree's configuration) that move links a and b apart: the
// sources of the steps on the path between them (mimic joints by their actuated sources),
// locked ones out.
std::vector<std::size_t> path_positions(const KinematicTree& tree, std::size_t a, std::size_t b,
                                        const std::map<std::string, double>& locked) {
  const auto up_a = steps_up(tree, a), up_b = steps_up(tree, b);
  const std::set<std::size_t> on_a(up_a.begin(), up_a.end()), on_b(up_b.begin(), up_b.end());
  std::set<std::size_t> out;
  for (const auto* side : {&up_a, &up_b})
    for (std::size_t k : *side) {
      const long source = tree.steps()[k].source;
      if ((on_a.count(k) && on_b.count(k)) || source < 0) continue;
      if (!locked.count(tree.joint_names()[std::size_t(source)])) out.insert(std::size_t(source));
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
  const std::vector<std::size_t> moving = path_positions(r.tree, a, b, r.locked);
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
