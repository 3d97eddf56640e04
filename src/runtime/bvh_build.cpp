#include "bvh_build.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <utility>

#include <Eigen/Eigenvalues>

#include "medspheres/assert.h"
#include "medspheres/sphere_tree.h"

namespace medspheres::detail {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Major, middle and minor axes of the centres' covariance, as columns; the third is the
// cross product of the first two so that the frame is right-handed.
Eigen::Matrix3d pca_axes(const std::vector<Ball>& balls) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Ball& b : balls) mean += b.center;
  mean /= static_cast<double>(balls.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Ball& b : balls) {
    const Eigen::Vector3d d = b.center - mean;
    cov.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  Eigen::Matrix3d axes;
  if (solver.info() != Eigen::Success) return Eigen::Matrix3d::Identity();
  // Eigenvalues come in increasing order.
  axes.col(0) = solver.eigenvectors().col(2).normalized();
  axes.col(1) = solver.eigenvectors().col(1).normalized();
  axes.col(2) = axes.col(0).cross(axes.col(1)).normalized();
  if (!axes.allFinite()) return Eigen::Matrix3d::Identity();
  return axes;
}

// Box, in the frame of `axes`, of the balls of one item, grown into [lo, hi].
void grow_box(const BuildInput& input, int item, const Eigen::Matrix3d& axes, Eigen::Vector3d& lo,
              Eigen::Vector3d& hi) {
  for (int k = input.ball_begin[static_cast<std::size_t>(item)];
       k < input.ball_begin[static_cast<std::size_t>(item) + 1]; ++k) {
    const Ball& b = input.balls[static_cast<std::size_t>(k)];
    const Eigen::Vector3d c = axes.transpose() * b.center;
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(b.radius);
    lo = lo.cwiseMin(c - r);
    hi = hi.cwiseMax(c + r);
  }
}

// The cut k of the sorted items (left child: the first k) with min_side <= k <= n -
// min_side that minimises k d(left) + (n - k) d(right), d the diagonal of the box of a
// side's balls in the node's PCA frame; the smallest such k. The diagonal stands for the
// size of the child's bounding volume: a pair traversal opens a node about as often as
// its volume comes near the other tree's, and then tests its items. On dilated sphere
// sets, where large interior spheres sit among many small surface ones, this visits up
// to a fifth fewer node pairs than the cut at the mean (a one-off comparison with that cut,
// docs/benchmarks.md).
int cheapest_cut(const BuildInput& input, const std::vector<std::pair<double, int>>& keyed,
                 const Eigen::Matrix3d& axes, int min_side, std::vector<double>& suffix) {
  const int n = static_cast<int>(keyed.size());
  const Eigen::Vector3d empty_lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  suffix.assign(static_cast<std::size_t>(n) + 1, 0.0);  // suffix[k]: d(items k .. n-1)
  Eigen::Vector3d lo = empty_lo, hi = -empty_lo;
  for (int i = n - 1; i >= 0; --i) {
    grow_box(input, keyed[static_cast<std::size_t>(i)].second, axes, lo, hi);
    suffix[static_cast<std::size_t>(i)] = (hi - lo).norm();
  }
  lo = empty_lo;
  hi = -empty_lo;
  int best_cut = n / 2;
  double best_cost = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= n - min_side; ++k) {
    grow_box(input, keyed[static_cast<std::size_t>(k) - 1].second, axes, lo, hi);
    if (k < min_side) continue;
    const double cost = k * (hi - lo).norm() + (n - k) * suffix[static_cast<std::size_t>(k)];
    if (cost < best_cost) {
      best_cost = cost;
      best_cut = k;
    }
  }
  return best_cut;
}

}  // namespace

std::vector<BuildNode> build_hierarchy(const BuildInput& input, int max_leaf_size,
                                       std::vector<int>& order) {
  const int n = static_cast<int>(input.split_points.size());
  MEDSPHERES_ASSERT(static_cast<int>(input.ball_begin.size()) == n + 1);
  order.resize(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::vector<BuildNode> nodes;
  if (n == 0) return nodes;
  nodes.reserve(static_cast<std::size_t>(2 * n));
  BuildNode root;
  root.begin = 0;
  root.end = n;
  nodes.push_back(root);

  std::vector<int> stack{0};
  std::vector<std::pair<double, int>> keyed;
  std::vector<double> suffix;
  std::vector<int> left, right;
  while (!stack.empty()) {
    const int index = stack.back();
    stack.pop_back();
    const int begin = nodes[static_cast<std::size_t>(index)].begin;
    const int end = nodes[static_cast<std::size_t>(index)].end;
    const std::vector<Ball> balls = balls_below(input, order, begin, end);
    nodes[static_cast<std::size_t>(index)].axes = pca_axes(balls);
    const int count = end - begin;
    if (count <= max_leaf_size) continue;

    // Split along the major axis: items sorted by the projection of their split points
    // (ties by item index), cut where cheapest_cut says.
    const Eigen::Matrix3d& axes = nodes[static_cast<std::size_t>(index)].axes;
    keyed.clear();
    for (int i = begin; i < end; ++i) {
      const int item = order[static_cast<std::size_t>(i)];
      keyed.emplace_back(input.split_points[static_cast<std::size_t>(item)].dot(axes.col(0)), item);
    }
    std::sort(keyed.begin(), keyed.end());
    const int cut = cheapest_cut(input, keyed, axes, count / 10 + 1, suffix);
    left.clear();
    right.clear();
    for (int i = 0; i < count; ++i)
      (i < cut ? left : right).push_back(keyed[static_cast<std::size_t>(i)].second);
    int out = begin;
    for (int item : left) order[static_cast<std::size_t>(out++)] = item;
    const int middle = out;
    for (int item : right) order[static_cast<std::size_t>(out++)] = item;

    const int first_child = static_cast<int>(nodes.size());
    const int depth = nodes[static_cast<std::size_t>(index)].depth + 1;
    nodes[static_cast<std::size_t>(index)].first_child = first_child;
    BuildNode a;
    a.begin = begin;
    a.end = middle;
    a.depth = depth;
    BuildNode b;
    b.begin = middle;
    b.end = end;
    b.depth = depth;
    nodes.push_back(a);
    nodes.push_back(b);
    stack.push_back(first_child + 1);
    stack.push_back(first_child);
  }
  return nodes;
}

std::vector<Ball> balls_below(const BuildInput& input, const std::vector<int>& order, int begin,
                              int end) {
  std::vector<Ball> balls;
  for (int i = begin; i < end; ++i) {
    const int item = order[static_cast<std::size_t>(i)];
    for (int k = input.ball_begin[static_cast<std::size_t>(item)];
         k < input.ball_begin[static_cast<std::size_t>(item) + 1]; ++k)
      balls.push_back(input.balls[static_cast<std::size_t>(k)]);
  }
  return balls;
}

double rss_containment_radius(const Rss& rss, const std::vector<Ball>& balls) {
  double need = 0.0;
  for (const Ball& b : balls) {
    const Eigen::Vector3d q = rss.axis.transpose() * (b.center - rss.corner);
    const double dx = q.x() - std::clamp(q.x(), 0.0, rss.length[0]);
    const double dy = q.y() - std::clamp(q.y(), 0.0, rss.length[1]);
    need = std::max(need, std::sqrt(dx * dx + dy * dy + q.z() * q.z()) + b.radius);
  }
  return need;
}

namespace {

// The rectangle of an RSS in its plane (x0 to x1 along the major and the middle axis) that
// comes within rho[i] of every ball's centre local[i]: the tightest extents with each ball
// taken along one axis only, then grown along the major axis for balls beyond a corner.
void rectangle_extents(const std::vector<Eigen::Vector3d>& local, const std::vector<double>& rho,
                       double x0[2], double x1[2]) {
  const std::size_t n = local.size();
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], local[i][k] + rho[i]);
      hi[k] = std::max(hi[k], local[i][k] - rho[i]);
    }
  }
  for (int k = 0; k < 2; ++k) {
    if (lo[k] <= hi[k]) {
      x0[k] = lo[k];
      x1[k] = hi[k];
    } else {
      x0[k] = x1[k] = 0.5 * (lo[k] + hi[k]);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double x = local[i].x(), y = local[i].y();
    const double dx = std::max({0.0, x0[0] - x, x - x1[0]});
    const double dy = std::max({0.0, x0[1] - y, y - x1[1]});
    if (dx > 0.0 && dy > 0.0 && dx * dx + dy * dy > rho[i] * rho[i]) {
      const double s = std::sqrt(std::max(0.0, rho[i] * rho[i] - dy * dy));
      if (x < x0[0])
        x0[0] = x + s;
      else
        x1[0] = x - s;
    }
  }
}

}  // namespace

Rss fit_rss(const Eigen::Matrix3d& axes, const std::vector<Ball>& balls) {
  MEDSPHERES_ASSERT(!balls.empty());
  const std::size_t n = balls.size();
  std::vector<Eigen::Vector3d> local(n);  // coordinates along the three axes
  double z_max = -std::numeric_limits<double>::infinity();
  double z_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    local[i] = axes.transpose() * balls[i].center;
    z_max = std::max(z_max, local[i].z() + balls[i].radius);
    z_min = std::min(z_min, local[i].z() - balls[i].radius);
  }
  // The thinnest slab along the minor axis that holds every ball fixes the radius.
  const double z0 = 0.5 * (z_max + z_min);
  const double radius = 0.5 * (z_max - z_min);

  // rho_i: how far the ball's centre may lie from the rectangle, within its plane.
  std::vector<double> rho(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double slack = radius - balls[i].radius;
    const double dz = local[i].z() - z0;
    rho[i] = std::sqrt(std::max(0.0, slack * slack - dz * dz));
  }
  double x0[2], x1[2];
  rectangle_extents(local, rho, x0, x1);
  Rss rss;
  const double lx = x1[0] - x0[0];
  const double ly = x1[1] - x0[1];
  rss.corner = axes.col(0) * x0[0] + axes.col(1) * x0[1] + axes.col(2) * z0;
  if (lx >= ly) {
    rss.axis = axes;
    rss.length = Eigen::Vector2d(lx, ly);
  } else {
    rss.axis.col(0) = axes.col(1);
    rss.axis.col(1) = axes.col(0);
    rss.axis.col(2) = -axes.col(2);
    rss.length = Eigen::Vector2d(ly, lx);
  }
  // Make containment hold for the stored values, then absorb the rounding of the check.
  const double need = std::max(radius, rss_containment_radius(rss, balls));
  const double extent = rss.corner.cwiseAbs().maxCoeff() + rss.length[0] + rss.length[1] + need;
  rss.radius = need + 16.0 * kEps * extent;
  return rss;
}

}  // namespace medspheres::detail
