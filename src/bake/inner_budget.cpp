#include "medspheres/bake/inner_budget.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ball_coverage.h"
#include "medspheres/error.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/number_text.h"

namespace medspheres {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Sample points deep in many candidates are thinned to about this many candidates' worth
// (ball_coverage.h): they are covered by the first choices whatever they are, and without
// thinning the centre of a convex solid, inside nearly every candidate, would hold most of
// the memberships.
constexpr std::uint32_t kCoverageDepth = 32;
// A start resolution without an inside grid vertex is doubled at most this many times.
constexpr int kInteriorRetries = 3;

void check_budget_options(std::size_t max_spheres, const InnerBudgetOptions& b) {
  if (max_spheres < 1) throw std::invalid_argument("max spheres must be >= 1");
  if (!(b.candidate_factor >= 1.0) || !std::isfinite(b.candidate_factor))
    throw std::invalid_argument("candidate_factor must be finite and >= 1, got " +
                                number_text(b.candidate_factor));
  if (b.samples != 0 && b.samples < 1000)
    throw std::invalid_argument("samples must be 0 (automatic) or >= 1000, got " +
                                std::to_string(b.samples));
  if (b.swap_passes < 0)
    throw std::invalid_argument("swap_passes must be >= 0, got " + std::to_string(b.swap_passes));
  if (b.max_resolution < kMinResolution || b.max_resolution > kMaxResolution)
    throw std::invalid_argument("max_resolution must be in [" + std::to_string(kMinResolution) +
                                ", " + std::to_string(kMaxResolution) + "], got " +
                                std::to_string(b.max_resolution));
}

struct CandidateBake {
  BakeResult bake;  // every bake's spheres, in bake order; stats of the finest bake
  std::vector<SearchStep> steps;
};

// Appends the spheres of `b` to `pool`; the stats become b's.
void append(BakeResult& pool, BakeResult&& b) {
  pool.spheres.spheres.insert(pool.spheres.spheres.end(), b.spheres.spheres.begin(),
                              b.spheres.spheres.end());
  pool.samples.insert(pool.samples.end(), b.samples.begin(), b.samples.end());
  pool.stats = std::move(b.stats);
}

// The candidate bakes (header): grow the resolution until the bakes have found `want`
// spheres together, a step of at least 1.5 times finds some spheres but no more than the
// bake before (the medial surface is resolved), or the limit. Each step aims the next bake at the
// spheres still missing.
CandidateBake bake_candidates(const MeshQuery& query, std::size_t want, BakeOptions options,
                              int max_resolution) {
  CandidateBake out;
  int r = std::clamp(options.resolution, kMinResolution, max_resolution);
  std::size_t previous = 0;
  double step = 0.0;  // the factor of the last growth step; 0 before the first bake
  for (int retries = 0;;) {
    options.resolution = r;
    BakeResult b;
    try {
      b = bake(query, options);
    } catch (const InputError&) {
      // No inside grid vertex (thin parts) or an ambiguous winding number: finer grids may
      // find the former, never the latter, so the retries are few.
      if (!out.steps.empty() || retries >= kInteriorRetries || r >= max_resolution) throw;
      ++retries;
      r = std::min(2 * r, max_resolution);
      continue;
    }
    const std::size_t n = b.spheres.size();
    out.steps.push_back({r, n, std::numeric_limits<double>::quiet_NaN()});
    append(out.bake, std::move(b));
    const std::size_t pooled = out.bake.spheres.size();
    // Bakes that find nothing are too coarse, never a sign of a resolved medial surface.
    const bool stalled = step >= 1.5 && n > 0 && n <= previous;
    if (pooled >= want || stalled || r >= max_resolution) break;
    previous = n;
    const double missing = static_cast<double>(want - pooled);
    step = n == 0 ? 2.0 : std::clamp(1.1 * std::sqrt(missing / n), 1.25, 2.0);
    r = std::min(max_resolution, static_cast<int>(std::ceil(r * step)));
  }
  return out;
}

// The chosen set and, per candidate, the weight of the points it would add (gain: its
// points covered by no chosen sphere) and, per chosen sphere, of the points only it covers
// (loss), kept exact through every addition and removal.
class Selection {
 public:
  explicit Selection(const BallCoverage& c)
      : c_(c),
        cover_(c.num_points(), 0),
        chosen_(c.points.size(), 0),
        gain_(c.points.size(), 0),
        loss_(c.points.size(), 0),
        overlap_(c.points.size(), 0) {
    for (std::size_t j = 0; j < gain_.size(); ++j)
      for (std::uint32_t p : c.points[j]) gain_[j] += c.weight[p];
  }

  void add(std::size_t j) {
    chosen_[j] = 1;
    for (std::uint32_t p : c_.points[j]) {
      const std::uint32_t before = cover_[p]++;
      const std::uint32_t w = c_.weight[p];
      if (before == 0) {
        for (std::size_t k = c_.offsets[p]; k < c_.offsets[p + 1]; ++k) gain_[c_.owners[k]] -= w;
        loss_[j] += w;
      } else if (before == 1) {
        loss_[sole_other_owner(p, j)] -= w;
      }
    }
  }

  void remove(std::size_t j) {
    chosen_[j] = 0;
    loss_[j] = 0;
    for (std::uint32_t p : c_.points[j]) {
      const std::uint32_t after = --cover_[p];
      const std::uint32_t w = c_.weight[p];
      if (after == 0) {
        for (std::size_t k = c_.offsets[p]; k < c_.offsets[p + 1]; ++k) gain_[c_.owners[k]] += w;
      } else if (after == 1) {
        loss_[sole_other_owner(p, j)] += w;
      }
    }
  }

  // Greedy: the largest gain, ties the lower index; without any gain, the largest radius.
  void greedy(std::size_t k, const std::vector<Sphere>& balls) {
    for (std::size_t step = 0; step < k; ++step) {
      std::size_t best = gain_.size();
      for (std::size_t j = 0; j < gain_.size(); ++j)
        if (!chosen_[j] && (best == gain_.size() || gain_[j] > gain_[best])) best = j;
      if (gain_[best] == 0) {
        fill_by_radius(k - step, balls);
        return;
      }
      add(best);
    }
  }

  // Passes of single swaps (header); returns the number of swaps made.
  std::size_t improve(int passes) {
    std::size_t swaps = 0;
    for (int pass = 0; pass < passes; ++pass) {
      bool changed = false;
      for (std::size_t i = 0; i < chosen_.size(); ++i) {
        if (!chosen_[i]) continue;
        const std::size_t j = best_replacement(i);
        if (j == chosen_.size()) continue;
        remove(i);
        add(j);
        ++swaps;
        changed = true;
      }
      if (!changed) break;
    }
    return swaps;
  }

  std::vector<std::size_t> chosen() const {
    std::vector<std::size_t> out;
    for (std::size_t j = 0; j < chosen_.size(); ++j)
      if (chosen_[j]) out.push_back(j);
    return out;
  }

 private:
  // The chosen owner of point p other than j (exactly one exists when called).
  std::size_t sole_other_owner(std::uint32_t p, std::size_t j) const {
    for (std::size_t k = c_.offsets[p]; k < c_.offsets[p + 1]; ++k) {
      const std::uint32_t q = c_.owners[k];
      if (q != j && chosen_[q]) return q;
    }
    throw std::logic_error("inner budget: coverage count out of step");
  }

  // The unchosen candidate that would cover the most points once i is dropped, if that is
  // more than i covers alone (ties: the lower index); chosen_.size() when none is.
  std::size_t best_replacement(std::size_t i) {
    std::vector<std::uint32_t> touched;
    for (std::uint32_t p : c_.points[i]) {
      if (cover_[p] != 1) continue;
      for (std::size_t k = c_.offsets[p]; k < c_.offsets[p + 1]; ++k) {
        const std::uint32_t q = c_.owners[k];
        if (chosen_[q]) continue;
        if (overlap_[q] == 0) touched.push_back(q);
        overlap_[q] += c_.weight[p];
      }
    }
    std::size_t best = chosen_.size();
    std::uint64_t best_value = loss_[i];
    for (std::size_t j = 0; j < chosen_.size(); ++j) {
      if (chosen_[j]) continue;
      const std::uint64_t value = gain_[j] + overlap_[j];
      if (value > best_value) {
        best_value = value;
        best = j;
      }
    }
    for (std::uint32_t q : touched) overlap_[q] = 0;
    return best;
  }

  void fill_by_radius(std::size_t k, const std::vector<Sphere>& balls) {
    std::vector<std::size_t> rest;
    for (std::size_t j = 0; j < chosen_.size(); ++j)
      if (!chosen_[j]) rest.push_back(j);
    std::stable_sort(rest.begin(), rest.end(), [&](std::size_t a, std::size_t b) {
      return balls[a].radius > balls[b].radius;
    });
    for (std::size_t t = 0; t < k && t < rest.size(); ++t) add(rest[t]);
  }

  const BallCoverage& c_;
  std::vector<std::uint32_t> cover_;  // chosen spheres covering each point
  std::vector<char> chosen_;
  std::vector<std::uint64_t> gain_, loss_;
  std::vector<std::uint64_t> overlap_;  // scratch of best_replacement, all 0 between calls
};

// InnerBudgetOptions::samples resolved. Small budgets need fewer points: the volumes that
// tell their choices apart are larger.
std::size_t sample_count(std::size_t max_spheres, const InnerBudgetOptions& b) {
  if (b.samples != 0) return b.samples;
  const std::size_t lo = std::size_t{1} << 15, hi = std::size_t{1} << 18;
  return max_spheres >= hi / 512 ? hi : std::max(lo, 512 * max_spheres);
}

// The volume the sample points should fill: the solid's, or when the mesh has none, the
// smaller of the box's and the balls' total.
double volume_estimate(const MeshQuery& query, const std::vector<Sphere>& balls) {
  if (const auto v = solid_volume(query.mesh())) return *v;
  double total = 0.0;
  for (const Sphere& b : balls) total += 4.0 / 3.0 * kPi * std::pow(b.radius, 3);
  return std::min(total, query.mesh().bounds().volume());
}

BakeResult keep(BakeResult all, const std::vector<std::size_t>& chosen) {
  BakeResult r;
  r.stats = all.stats;
  for (std::size_t j : chosen) {
    r.spheres.spheres.push_back(all.spheres.spheres[j]);
    r.samples.push_back(all.samples[j]);
  }
  r.stats.spheres = r.spheres.size();
  r.stats.min_radius = std::numeric_limits<double>::infinity();
  r.stats.max_radius = 0.0;
  for (const Sphere& s : r.spheres.spheres) {
    r.stats.min_radius = std::min(r.stats.min_radius, s.radius);
    r.stats.max_radius = std::max(r.stats.max_radius, s.radius);
  }
  return r;
}

}  // namespace

BakeResult bake_inner_budget(const MeshQuery& query, std::size_t max_spheres,
                             const BakeOptions& options, const InnerBudgetOptions& budget) {
  const auto t0 = std::chrono::steady_clock::now();
  check_budget_options(max_spheres, budget);
  validate_bake_options(options);
  // Every resolution up to the finest the candidate bakes may reach.
  if (const auto problem =
          medial_tolerance_problem(options.medial_tolerance,
                                   query.mesh().bounds().sizes().maxCoeff(), budget.max_resolution))
    throw *problem;
  const double want = std::ceil(budget.candidate_factor * static_cast<double>(max_spheres));
  CandidateBake found = bake_candidates(query, static_cast<std::size_t>(std::min(want, 1e15)),
                                        options, budget.max_resolution);
  if (found.bake.spheres.empty()) {
    std::string tried;
    for (const SearchStep& s : found.steps)
      tried += (tried.empty() ? "" : ", ") + std::to_string(s.resolution);
    throw InputError::option(ErrorKind::kUnreachable, "max_spheres", std::to_string(max_spheres),
                             "no resolution tried (" + tried + ") gives any sphere");
  }
  const std::vector<Sphere>& balls = found.bake.spheres.spheres;
  std::vector<std::size_t> chosen;
  if (balls.size() <= max_spheres) {
    for (std::size_t j = 0; j < balls.size(); ++j) chosen.push_back(j);
  } else {
    if (options.progress) options.progress("selecting", 0, max_spheres);
    const BallCoverage coverage =
        sample_ball_coverage(balls, query.mesh().bounds(), volume_estimate(query, balls),
                             sample_count(max_spheres, budget), kCoverageDepth, options.threads);
    Selection selection(coverage);
    selection.greedy(max_spheres, balls);
    selection.improve(budget.swap_passes);
    chosen = selection.chosen();
    if (options.progress) options.progress("selecting", max_spheres, max_spheres);
  }
  BakeResult result = keep(std::move(found.bake), chosen);
  result.stats.search = std::move(found.steps);
  result.stats.total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace medspheres
