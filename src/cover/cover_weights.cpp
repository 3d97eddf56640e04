// The protrusion weights of the covering bake (cover_weights.h). The region's points are few
// (a planner's contact region: hundreds to thousands), and a weight is asked once per ball
// or candidate centre per step: the nearest point is found by a scan.
#include "cover_weights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/number_text.h"

namespace medspheres {

std::string protrusion_weights_problem(const ProtrusionWeights& w) {
  if (!std::isfinite(w.reach) || w.reach < 0.0)
    return "weights.reach must be finite and >= 0, got " + number_text(w.reach);
  if (!std::isfinite(w.weight) || w.weight < 1.0)
    return "weights.weight must be finite and >= 1, got " + number_text(w.weight);
  for (const Eigen::Vector3d& p : w.points)
    if (!p.allFinite()) return "weights.points holds a non-finite point";
  return "";
}

namespace detail {

BallWeights::BallWeights(const ProtrusionWeights& w) {
  if (!w.active()) return;
  points_ = w.points;
  reach_ = w.reach;
  weight_ = w.weight;
}

double BallWeights::gap(const Eigen::Vector3d& c) const {
  double least = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : points_) least = std::min(least, (p - c).squaredNorm());
  return std::sqrt(least) - reach_;
}

std::vector<double> weighted(const std::vector<Sphere>& balls, const BallWeights& w,
                             std::vector<double> p) {
  if (!w.active()) return p;
  for (std::size_t j = 0; j < p.size(); ++j) p[j] *= w.weight(balls[j]);
  return p;
}

void assign_weighted(const Elements& e, const std::vector<Sphere>& balls,
                     const std::vector<double>& depth, const BallWeights& w,
                     std::vector<int>& owner, int threads) {
  std::vector<double> gap(balls.size());
  for (std::size_t j = 0; j < balls.size(); ++j) gap[j] = w.gap(balls[j].center);
  owner.assign(e.size(), 0);
  const long long n = static_cast<long long>(e.size());
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long ii = 0; ii < n; ++ii) {
    const std::size_t i = static_cast<std::size_t>(ii);
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < balls.size(); ++j) {
      const double R = std::max(balls[j].radius, farthest(e, i, balls[j].center));
      const double cost = w.weight(R, gap[j]) * (R - depth[j]);
      if (cost < least) least = cost, owner[i] = static_cast<int>(j);
    }
  }
}

double largest_weighted_protrusion(const MeshQuery& query, const std::vector<Sphere>& balls,
                                   const BallWeights& w, int threads) {
  std::vector<Sphere> live;
  for (const Sphere& b : balls)
    if (b.radius > 0.0) live.push_back(b);
  const std::vector<double> p = weighted(live, w, sphere_protrusions(query, live, threads));
  return p.empty() ? 0.0 : *std::max_element(p.begin(), p.end());
}

}  // namespace detail

}  // namespace medspheres
