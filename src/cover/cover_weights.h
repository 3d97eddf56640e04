#pragma once
// Private to the covering bake (cover.cpp): the protrusion weights of
// medspheres/cover/protrusion_weights.h on the bake's balls.

#include <vector>

#include "cover_elements.h"
#include "medspheres/cover/protrusion_weights.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"

namespace medspheres::detail {

// A ball centred at c weighs w.weight when its radius reaches `gap(c)`: the distance from c
// to the nearest point of w less w.reach (some point is then within reach of the ball); 1
// otherwise. Inactive (no points, or weight 1): every ball weighs 1.
class BallWeights {
 public:
  BallWeights() = default;
  explicit BallWeights(const ProtrusionWeights& w);
  bool active() const { return !points_.empty(); }
  double gap(const Eigen::Vector3d& c) const;
  double weight(double radius, double gap) const { return radius >= gap ? weight_ : 1.0; }
  double weight(const Sphere& b) const { return active() ? weight(b.radius, gap(b.center)) : 1.0; }

 private:
  std::vector<Eigen::Vector3d> points_;
  double reach_ = 0.0, weight_ = 1.0;
};

// The balls' protrusions \p p (one per ball), each times its ball's weight.
std::vector<double> weighted(const std::vector<Sphere>& balls, const BallWeights& w,
                             std::vector<double> p);

// The minimax rounds' assignment under weights: each element i to the ball j whose weighted
// protrusion would be least once it holds i: with R = max(r_j, farthest point of i from
// c_j), weight(R) (R - depth_j) (ties: lowest index). \p depth: one per ball.
void assign_weighted(const Elements& e, const std::vector<Sphere>& balls,
                     const std::vector<double>& depth, const BallWeights& w,
                     std::vector<int>& owner, int threads);

// The largest weighted protrusion of the balls of radius > 0 (0 for none).
double largest_weighted_protrusion(const MeshQuery& query, const std::vector<Sphere>& balls,
                                   const BallWeights& w, int threads);

}  // namespace medspheres::detail
