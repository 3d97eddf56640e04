// SphereTree construction: structure, accessors against their definitions, bounding
// volumes containing their spheres, minimum enclosing balls against CGAL's exact
// Min_sphere_of_spheres_d.

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include <CGAL/Cartesian.h>
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_3.h>
#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/sphere_tree.h"
#include "support/sphere_fixtures.h"

using medspheres::BoundingVolumeKind;
using medspheres::Rss;
using medspheres::Sphere;
using medspheres::SphereSet;
using medspheres::SphereTree;
using medspheres::SphereTreeOptions;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Distance from p to the rectangle of rss, by the definition in rss.h: coordinates in
// frame T, clamped to [0, l0] x [0, l1] x {0}.
double rectangle_distance(const Rss& rss, const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = rss.axis.transpose() * (p - rss.corner);
  const double x = std::clamp(q.x(), 0.0, rss.length[0]);
  const double y = std::clamp(q.y(), 0.0, rss.length[1]);
  return Eigen::Vector3d(q.x() - x, q.y() - y, q.z()).norm();
}

std::vector<SphereSet> sample_sets() {
  std::mt19937 rng(7);
  std::vector<SphereSet> sets;
  sets.push_back(medspheres::test::random_sphere_set(rng, 1));
  sets.push_back(medspheres::test::random_sphere_set(rng, 2));
  sets.push_back(medspheres::test::random_sphere_set(rng, 37));
  sets.push_back(medspheres::test::random_sphere_set(rng, 300, 5.0, 0.01, 1.0));
  sets.push_back(medspheres::test::random_sheet_set(rng, 250));
  // Degenerate: identical spheres, collinear centres, coplanar centres, nested spheres.
  SphereSet same;
  for (int i = 0; i < 9; ++i) same.spheres.push_back({Eigen::Vector3d(0.5, -0.25, 1.0), 0.125});
  sets.push_back(same);
  SphereSet line;
  for (int i = 0; i < 20; ++i) line.spheres.push_back({Eigen::Vector3d(0.1 * i, 0, 0), 0.05});
  sets.push_back(line);
  SphereSet plane;
  for (int i = 0; i < 40; ++i)
    plane.spheres.push_back({Eigen::Vector3d(0.1 * (i % 7), 0.13 * (i / 7), 2.0), 0.07});
  sets.push_back(plane);
  SphereSet nested;
  for (int i = 1; i <= 6; ++i) nested.spheres.push_back({Eigen::Vector3d(0.01 * i, 0, 0), 0.1 * i});
  sets.push_back(nested);
  // Far from the origin, to exercise rounding margins.
  SphereSet far = medspheres::test::random_sphere_set(rng, 60, 0.5);
  for (Sphere& s : far.spheres) s.center += Eigen::Vector3d(1e4, -3e4, 2e4);
  sets.push_back(far);
  return sets;
}

// Walks the tree from the root and checks it is a binary tree over all spheres.
void check_structure(const SphereTree& tree, const SphereSet& set, int max_leaf) {
  const medspheres::SphereTreeStats stats = tree.stats();
  std::vector<int> visits(tree.num_nodes(), 0);
  std::size_t leaves = 0, depth = 0, min_leaf = set.size(), max_leaf_seen = 0;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [node, d] = stack.back();
    stack.pop_back();
    REQUIRE(node < tree.num_nodes());
    ++visits[node];
    depth = std::max(depth, d);
    const std::vector<std::size_t> below = tree.spheres_below(node);
    if (tree.is_leaf(node)) {
      ++leaves;
      CHECK(below.size() >= 1);
      CHECK(below.size() <= static_cast<std::size_t>(max_leaf));
      min_leaf = std::min(min_leaf, below.size());
      max_leaf_seen = std::max(max_leaf_seen, below.size());
      CHECK_THROWS_AS(tree.left_child(node), std::invalid_argument);
    } else {
      const std::size_t l = tree.left_child(node), r = tree.right_child(node);
      CHECK(r == l + 1);
      std::vector<std::size_t> joined = tree.spheres_below(l);
      const std::vector<std::size_t> right = tree.spheres_below(r);
      CHECK(!joined.empty());
      CHECK(!right.empty());
      joined.insert(joined.end(), right.begin(), right.end());
      CHECK(joined == below);
      stack.push_back({l, d + 1});
      stack.push_back({r, d + 1});
    }
  }
  for (int v : visits) CHECK(v == 1);
  std::vector<std::size_t> all = tree.spheres_below(0);
  std::sort(all.begin(), all.end());
  std::vector<std::size_t> expected(set.size());
  std::iota(expected.begin(), expected.end(), 0);
  CHECK(all == expected);
  CHECK(stats.spheres == set.size());
  CHECK(stats.nodes == tree.num_nodes());
  CHECK(stats.nodes == 2 * leaves - 1);
  CHECK(stats.leaves == leaves);
  CHECK(stats.depth == depth);
  CHECK(stats.min_leaf_size == min_leaf);
  CHECK(stats.max_leaf_size == max_leaf_seen);
  CHECK(stats.mean_leaf_size == Approx(static_cast<double>(set.size()) / leaves));
  CHECK(stats.bytes >= set.size() * (4 * sizeof(double) + 2 * sizeof(std::int32_t)));
  CHECK(static_cast<double>(depth) <=
        std::log(static_cast<double>(set.size())) / std::log(10.0 / 9.0) + 1.0);
}

}  // namespace

TEST_CASE("SphereTree: an empty set gives an empty tree", "[sphere_tree]") {
  const SphereTree tree{SphereSet{}};
  CHECK(tree.empty());
  CHECK(tree.num_nodes() == 0);
  CHECK(tree.num_spheres() == 0);
  CHECK(tree.stats().nodes == 0);
  CHECK_THROWS_AS(tree.is_leaf(0), std::out_of_range);
  CHECK_THROWS_AS(tree.sphere(0), std::out_of_range);
  const SphereTree defaulted;
  CHECK(defaulted.empty());
  CHECK(defaulted.stats().nodes == 0);
}

TEST_CASE("SphereTree: bad input and bad options are rejected", "[sphere_tree]") {
  SphereSet set;
  set.spheres.push_back({Eigen::Vector3d(0, 0, 0), 1.0});
  SphereTreeOptions options;
  options.max_leaf_size = 0;
  CHECK_THROWS_AS(SphereTree(set, options), std::invalid_argument);
  set.spheres.push_back({Eigen::Vector3d(0, 0, 0), -1.0});
  CHECK_THROWS_AS(SphereTree(set), medspheres::InputError);
  set.spheres.back().radius = 1.0;
  set.spheres.back().center.x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(SphereTree(set), medspheres::InputError);
  const SphereTree tree(SphereSet{{{Eigen::Vector3d(1, 2, 3), 0.5}}, "{}"});
  CHECK_THROWS_AS(tree.is_leaf(1), std::out_of_range);
  CHECK_THROWS_AS(tree.rss(7), std::out_of_range);
  SphereTreeOptions ball;
  ball.kind = BoundingVolumeKind::ball;
  const SphereTree ball_tree(SphereSet{{{Eigen::Vector3d(1, 2, 3), 0.5}}, "{}"}, ball);
  CHECK_THROWS_AS(ball_tree.rss(0), std::invalid_argument);
}

TEST_CASE("SphereTree: structure and statistics match their definitions", "[sphere_tree]") {
  for (const SphereSet& set : sample_sets()) {
    for (BoundingVolumeKind kind : {BoundingVolumeKind::rss, BoundingVolumeKind::ball}) {
      for (int leaf : {1, 3}) {
        SphereTreeOptions options;
        options.kind = kind;
        options.max_leaf_size = leaf;
        const SphereTree tree(set, options);
        CHECK(tree.kind() == kind);
        CHECK(tree.num_spheres() == set.size());
        check_structure(tree, set, leaf);
        for (std::size_t i = 0; i < set.size(); ++i) {
          CHECK(tree.sphere(i).center == set.spheres[i].center);
          CHECK(tree.sphere(i).radius == set.spheres[i].radius);
        }
        for (std::size_t node = 0; node < tree.num_nodes(); ++node) {
          double max_r = 0.0;
          for (std::size_t i : tree.spheres_below(node))
            max_r = std::max(max_r, set.spheres[i].radius);
          CHECK(tree.max_sphere_radius(node) == max_r);
        }
      }
    }
  }
}

TEST_CASE("SphereTree: every RSS node contains its spheres", "[sphere_tree]") {
  for (const SphereSet& set : sample_sets()) {
    for (int leaf : {1, 4}) {
      SphereTreeOptions options;
      options.max_leaf_size = leaf;
      const SphereTree tree(set, options);
      for (std::size_t node = 0; node < tree.num_nodes(); ++node) {
        const Rss rss = tree.rss(node);
        // Axes: orthonormal and right-handed; sides ordered.
        CHECK((rss.axis.transpose() * rss.axis - Eigen::Matrix3d::Identity()).norm() < 1e-12);
        CHECK(rss.axis.determinant() == Approx(1.0).margin(1e-12));
        CHECK(rss.length[0] >= rss.length[1]);
        CHECK(rss.length[1] >= 0.0);
        CHECK(rss.radius >= 0.0);
        // center(): the midpoint of the minimum and maximum corners.
        const Eigen::Vector3d far_corner =
            rss.corner + rss.axis.col(0) * rss.length[0] + rss.axis.col(1) * rss.length[1];
        CHECK((rss.center() - 0.5 * (rss.corner + far_corner)).norm() <=
              8 * kEps * (rss.corner.norm() + far_corner.norm()));
        const Sphere ball = tree.bounding_ball(node);
        for (std::size_t i : tree.spheres_below(node)) {
          const Sphere& s = set.spheres[i];
          CHECK(rectangle_distance(rss, s.center) + s.radius <= rss.radius);
          CHECK((s.center - ball.center).norm() + s.radius <= ball.radius);
        }
      }
      // A leaf with one sphere is that sphere.
      if (leaf == 1) {
        for (std::size_t node = 0; node < tree.num_nodes(); ++node) {
          if (!tree.is_leaf(node)) continue;
          const Rss rss = tree.rss(node);
          const Sphere& s = set.spheres[tree.spheres_below(node)[0]];
          CHECK(rss.length[0] == 0.0);
          CHECK(rss.radius == Approx(s.radius).epsilon(1e-12).margin(1e-12 * s.center.norm()));
        }
      }
    }
  }
}

TEST_CASE("SphereTree: RSS nodes are tight across a flat sheet", "[sphere_tree]") {
  std::mt19937 rng(11);
  const SphereSet set = medspheres::test::random_sheet_set(rng, 400);
  const SphereTree tree(set);
  // The root's slab is no thicker than the spheres' extent along its normal.
  const Rss root = tree.rss(0);
  double lo = 1e300, hi = -1e300;
  for (const Sphere& s : set.spheres) {
    const double z = root.axis.col(2).dot(s.center);
    lo = std::min(lo, z - s.radius);
    hi = std::max(hi, z + s.radius);
  }
  CHECK(2 * root.radius >= hi - lo);
  CHECK(2 * root.radius <= (hi - lo) * (1 + 1e-9) + 1e-12);
}

TEST_CASE("SphereTree: bounding balls are minimum enclosing balls (CGAL oracle)", "[sphere_tree]") {
  using Traits =
      CGAL::Min_sphere_of_spheres_d_traits_3<CGAL::Cartesian<double>, double, CGAL::Tag_true>;
  using MinSphere = CGAL::Min_sphere_of_spheres_d<Traits>;
  for (const SphereSet& set : sample_sets()) {
    for (BoundingVolumeKind kind : {BoundingVolumeKind::ball, BoundingVolumeKind::rss}) {
      SphereTreeOptions options;
      options.kind = kind;
      options.max_leaf_size = 2;
      const SphereTree tree(set, options);
      for (std::size_t node = 0; node < tree.num_nodes(); ++node) {
        std::vector<Traits::Sphere> input;
        for (std::size_t i : tree.spheres_below(node)) {
          const Sphere& s = set.spheres[i];
          input.emplace_back(Traits::Point(s.center.x(), s.center.y(), s.center.z()), s.radius);
        }
        MinSphere exact(input.begin(), input.end());
        REQUIRE(exact.is_valid());
        const double exact_radius = exact.radius();
        const Sphere ball = tree.bounding_ball(node);
        for (std::size_t i : tree.spheres_below(node)) {
          const Sphere& s = set.spheres[i];
          CHECK((s.center - ball.center).norm() + s.radius <= ball.radius);
        }
        const double rounding = 64 * kEps * (ball.center.norm() + ball.radius);
        CHECK(ball.radius >= exact_radius - rounding);
        CHECK(ball.radius <= exact_radius * (1 + SphereTree::ball_slack) + rounding);
      }
    }
  }
}
