// The minimum enclosing ball of balls (min_enclosing_ball.h).
//
// Cutting planes: the smallest ball of a finite set P of points taken on the input spheres
// is no larger than the answer, and the ball of its centre that encloses every input ball
// is no smaller. Each round adds, for every ball that sticks out of the current point
// ball, its farthest point from the current centre, and solves the point problem again
// (Welzl's algorithm); the radius of the point ball grows strictly, and the loop stops
// once the enclosing radius at its centre is within kEnclosingBallSlack of it, which
// bounds the answer's excess over the minimum by the same factor.
#include "medspheres/min_enclosing_ball.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <list>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

#include "medspheres/assert.h"

namespace medspheres {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

void check(const std::vector<Sphere>& balls) {
  if (balls.empty()) throw std::invalid_argument("min_enclosing_ball: no balls");
  for (std::size_t i = 0; i < balls.size(); ++i)
    if (!balls[i].center.allFinite() || !std::isfinite(balls[i].radius) || balls[i].radius < 0.0)
      throw std::invalid_argument("min_enclosing_ball: ball " + std::to_string(i) +
                                  " has a non-finite centre or a radius that is negative or "
                                  "not finite");
}

// The exact (to rounding) smallest ball containing a finite point set: Welzl's
// move-to-front algorithm with an explicit support set of at most four points, as in
// Gärtner's "Fast and robust smallest enclosing balls" (1999). A point that is affinely
// dependent on the current support set, up to a relative tolerance, is not pushed; the
// caller's cutting-plane loop makes the final ball enclose everything regardless.
class PointMiniball {
 public:
  explicit PointMiniball(std::list<Eigen::Vector3d>& points) : points_(points) {
    mtf(points_.end());
  }

  const Eigen::Vector3d& center() const { return center_; }
  double radius() const { return sqr_radius_ < 0.0 ? 0.0 : std::sqrt(sqr_radius_); }

 private:
  // The smallest ball of the points before `end` with the support set on its boundary.
  // The current ball is changed by push() only: after a recursive call it is the ball
  // that call found, which is what the loop continues from.
  void mtf(std::list<Eigen::Vector3d>::iterator end) {
    if (size_ == 4) return;
    for (auto it = points_.begin(); it != end;) {
      const auto next = std::next(it);
      const double e = (*it - center_).squaredNorm() - sqr_radius_;
      if (e > 1e-13 * std::max(sqr_radius_, 0.0) && push(*it)) {
        mtf(it);
        --size_;
        points_.splice(points_.begin(), points_, it);
      }
      it = next;
    }
  }

  // Adds p to the support set and makes the current ball the smallest one with the whole
  // support set on its boundary; false (and no change) when p is nearly affinely
  // dependent on the set.
  bool push(const Eigen::Vector3d& p) {
    const int k = size_;  // points already in the support set
    if (k == 0) {
      support_[0] = p;
      center_ = p;
      sqr_radius_ = 0.0;
      size_ = 1;
      return true;
    }
    // Centre c = q0 + sum_j lambda_j d_j with d_j = q_j - q0, j = 1..k, and
    // 2 d_j . (c - q0) = |d_j|^2.
    support_[k] = p;
    Eigen::Matrix<double, 3, Eigen::Dynamic> d(3, k);
    for (int j = 1; j <= k; ++j) d.col(j - 1) = support_[j] - support_[0];
    const Eigen::MatrixXd gram = d.transpose() * d;
    double diag_product = 1.0;
    for (int j = 0; j < k; ++j) diag_product *= gram(j, j);
    if (!(diag_product > 0.0)) return false;
    if (!(gram.determinant() > 1e-12 * diag_product)) return false;
    Eigen::VectorXd rhs(k);
    for (int j = 0; j < k; ++j) rhs[j] = 0.5 * gram(j, j);
    const Eigen::VectorXd lambda = gram.partialPivLu().solve(rhs);
    const Eigen::Vector3d offset = d * lambda;
    if (!offset.allFinite()) return false;
    center_ = support_[0] + offset;
    sqr_radius_ = offset.squaredNorm();
    size_ = k + 1;
    return true;
  }

  std::list<Eigen::Vector3d>& points_;
  Eigen::Vector3d support_[4];
  Eigen::Vector3d center_ = Eigen::Vector3d::Zero();
  double sqr_radius_ = -1.0;  // negative: the empty ball
  int size_ = 0;
};

// The farthest point of ball b from x, and its distance.
Eigen::Vector3d farthest_point(const Sphere& b, const Eigen::Vector3d& x) {
  const Eigen::Vector3d v = b.center - x;
  const double len = v.norm();
  if (len > 0.0) return b.center + v * (b.radius / len);
  return b.center + Eigen::Vector3d::UnitX() * b.radius;
}

double enclosing_radius(const std::vector<Sphere>& balls, const Eigen::Vector3d& c) {
  double r = 0.0;
  for (const Sphere& b : balls) r = std::max(r, (b.center - c).norm() + b.radius);
  return r;
}

}  // namespace

Sphere min_enclosing_ball(const std::vector<Sphere>& balls) {
  check(balls);
  if (balls.size() == 1) return balls.front();

  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const Sphere& b : balls) center += b.center;
  center /= static_cast<double>(balls.size());

  // Cutting planes: P holds points on the spheres, so its smallest ball (radius r_p)
  // is no larger than the answer; stop once the ball of the same centre that encloses
  // every sphere is within kEnclosingBallSlack of it.
  std::list<Eigen::Vector3d> points;
  double r_p = -1.0;
  // Each round grows r_p strictly; 200 rounds are far more than the tests ever need.
  constexpr int kMaxRounds = 200;
  for (int round = 0; round <= kMaxRounds; ++round) {
    const double r = enclosing_radius(balls, center);
    if (r_p >= 0.0 && r <= r_p * (1.0 + kEnclosingBallSlack)) break;
    MEDSPHERES_ASSERT(round < kMaxRounds);
    if (round == kMaxRounds) break;
    const double add_above = r_p * (1.0 + 0.5 * kEnclosingBallSlack);
    for (const Sphere& b : balls) {
      if ((b.center - center).norm() + b.radius > add_above)
        points.push_back(farthest_point(b, center));
    }
    const PointMiniball miniball(points);
    center = miniball.center();
    r_p = miniball.radius();
  }
  Sphere ball;
  ball.center = center;
  const double r = enclosing_radius(balls, center);
  ball.radius = r + 16.0 * kEps * (center.cwiseAbs().maxCoeff() + r);
  return ball;
}

}  // namespace medspheres
