// Sharing a sphere budget among the links of a robot.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "medspheres/error.h"
#include "medspheres/number_text.h"
#include "medspheres/robot_bake/robot_bake.h"

namespace medspheres {

namespace {

double surface_area(const LinkSolid& solid) {
  double area = 0.0;
  for (const LinkSolidPart& part : solid.parts)
    for (std::size_t t = 0; t < part.mesh.num_triangles(); ++t) {
      const Eigen::Vector3d a = part.mesh.corner(t, 0);
      area += 0.5 * (part.mesh.corner(t, 1) - a).cross(part.mesh.corner(t, 2) - a).norm();
    }
  return area;
}

// What a bake may make when its link may have `total` spheres in all.
std::size_t for_bake(std::size_t total, const LinkSolid& solid) {
  return total > solid.spheres.size() ? total - solid.spheres.size() : 1;
}

// Shares `spare` spheres among `links` in proportion to `weights`: floors first, then one
// more to the largest remainders, ties to the lower index.
std::vector<std::size_t> largest_remainders(std::size_t spare, const std::vector<double>& weights) {
  const double sum = std::accumulate(weights.begin(), weights.end(), 0.0);
  std::vector<std::size_t> share(weights.size(), 0);
  std::vector<double> remainder(weights.size(), 0.0);
  std::size_t given = 0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    const double exact = sum > 0.0 ? static_cast<double>(spare) * weights[i] / sum
                                   : static_cast<double>(spare) / weights.size();
    share[i] = static_cast<std::size_t>(std::floor(exact));
    remainder[i] = exact - std::floor(exact);
    given += share[i];
  }
  std::vector<std::size_t> order(weights.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
  for (std::size_t k = 0; given < spare && k < order.size(); ++k, ++given) ++share[order[k]];
  return share;
}

void check_overrides(const std::vector<LinkSolid>& solids, const RobotBudget& budget,
                     const std::string& source) {
  for (const auto& [name, k] : budget.links) {
    const auto it = std::find_if(solids.begin(), solids.end(),
                                 [&link = name](const LinkSolid& s) { return s.link == link; });
    if (it == solids.end())
      throw InputError::option(ErrorKind::kOutOfRange, "link", "",
                               "no link named '" + name + "' in " + source);
    if (it->parts.empty())
      throw InputError::option(ErrorKind::kOutOfRange, "link", "",
                               "link '" + name + "' of " + source +
                                   " has no meshed geometry to bake (its spheres are exact)");
    if (k == 0)
      throw InputError::option(ErrorKind::kOutOfRange, "link", "",
                               "link '" + name + "': the budget must be >= 1");
  }
}

}  // namespace

std::vector<std::optional<std::size_t>> link_bake_budgets(const std::vector<LinkSolid>& solids,
                                                          const RobotBudget& budget,
                                                          const std::string& source) {
  if (budget.per_link && budget.total)
    throw InputError::option(ErrorKind::kConflict, "budget", "",
                             "cannot be combined with spheres_per_link", {}, {"spheres_per_link"});
  if (budget.per_link && *budget.per_link == 0)
    throw InputError::option(ErrorKind::kOutOfRange, "spheres_per_link", "", "must be >= 1");
  check_overrides(solids, budget, source);
  std::vector<std::optional<std::size_t>> out(solids.size());
  std::size_t fixed = 0;
  std::vector<std::size_t> shared;  // links that take part in the total's sharing
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const LinkSolid& s = solids[i];
    const auto over = budget.links.find(s.link);
    if (s.parts.empty()) {
      fixed += s.spheres.size();
    } else if (over != budget.links.end()) {
      out[i] = for_bake(over->second, s);
      fixed += std::max(over->second, s.spheres.size() + 1);
    } else if (budget.per_link) {
      out[i] = for_bake(*budget.per_link, s);
    } else if (budget.total) {
      fixed += s.spheres.size();
      shared.push_back(i);
    }
  }
  if (!budget.total || shared.empty()) return out;
  if (*budget.total < fixed + shared.size())
    throw InputError::option(ErrorKind::kOutOfRange, "budget", "",
                             std::to_string(*budget.total) + " is too small for " + source +
                                 ": the exact sphere primitives and the per-link overrides take " +
                                 std::to_string(fixed) + " and " +
                                 count_text(shared.size(), "link") +
                                 " to bake need at least 1 each");
  std::vector<double> areas;
  for (std::size_t i : shared) areas.push_back(surface_area(solids[i]));
  const std::vector<std::size_t> extra =
      largest_remainders(*budget.total - fixed - shared.size(), areas);
  for (std::size_t k = 0; k < shared.size(); ++k) out[shared[k]] = 1 + extra[k];
  return out;
}

}  // namespace medspheres
