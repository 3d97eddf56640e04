// Walks of a sphere tree against a ProximityTarget (src/runtime/traversal/traversal_target.h):
// nodes bounded by boxes (TargetNode::box_half) give the answers of the same nodes bounded by their
// RSS alone, and of brute force over the cells; a walk run inside another walk's target keeps its
// own node stack, so the outer walk's answers do not change.

#include <algorithm>
#include <cstddef>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/sphere_tree.h"
#include "support/proximity_targets.h"
#include "support/sphere_fixtures.h"

namespace ms = medspheres;
namespace mt = medspheres::test;

namespace {

constexpr int kDepth = 3;
constexpr double kHalf = 0.8;

std::vector<bool> random_cells(std::mt19937& rng) {
  const int n = 1 << kDepth;
  std::vector<bool> occupied(static_cast<std::size_t>(n * n * n));
  std::bernoulli_distribution coin(0.15);
  for (std::size_t k = 0; k < occupied.size(); ++k) occupied[k] = coin(rng);
  return occupied;
}

// Brute force: every sphere against every occupied cell (solid cubes), in the grid's frame.
struct Brute {
  double min_signed = std::numeric_limits<double>::infinity();
  std::size_t overlaps = 0;
};

Brute brute(const ms::SphereSet& set, const Eigen::Isometry3d& X_WA,
            const std::vector<bool>& occupied, const Eigen::Isometry3d& X_WB) {
  const int n = 1 << kDepth;
  const double s = 2.0 * kHalf / n;
  Brute out;
  for (const ms::Sphere& sphere : set.spheres) {
    const Eigen::Vector3d c = X_WB.inverse() * (X_WA * sphere.center);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          if (!occupied[static_cast<std::size_t>(i + n * (j + n * k))]) continue;
          const Eigen::Vector3d lo(-kHalf + s * i, -kHalf + s * j, -kHalf + s * k);
          const double d =
              mt::ball_box_proximity(lo, lo + Eigen::Vector3d::Constant(s), c, sphere.radius)
                  .distance;
          out.min_signed = std::min(out.min_signed, d);
          if (d <= 0.0) ++out.overlaps;
        }
  }
  return out;
}

// A grid whose children() first runs a whole walk of its own (against another grid), as a
// target whose answers query would.
class QueryingGrid final : public mt::CubeGridTarget {
 public:
  QueryingGrid(std::vector<bool> occupied, const ms::SphereTree& probe,
               const mt::CubeGridTarget& other)
      : CubeGridTarget(kDepth, kHalf, std::move(occupied), true), probe_(probe), other_(other) {}

  int children(const ms::TargetNode& parent, ms::TargetNode* out) const override {
    const ms::TreeDistance inner =
        ms::distance(probe_, Eigen::Isometry3d::Identity(), other_, Eigen::Isometry3d::Identity());
    if (!inner.found()) return 0;  // never: the probe is a set of spheres near the grid
    return CubeGridTarget::children(parent, out);
  }

 private:
  const ms::SphereTree& probe_;
  const mt::CubeGridTarget& other_;
};

}  // namespace

TEST_CASE("Target nodes bounded by boxes give the answers of RSS bounds and of brute force",
          "[sphere_tree][query][target]") {
  std::mt19937 rng(51);
  int apart = 0, overlapping = 0;
  for (int scene = 0; scene < 40; ++scene) {
    const std::vector<bool> occupied = random_cells(rng);
    const mt::CubeGridTarget rss(kDepth, kHalf, occupied), box(kDepth, kHalf, occupied, true);
    const ms::SphereSet set = mt::random_sphere_set(rng, 1 + rng() % 40, 0.5, 0.02, 0.15);
    const ms::SphereTree tree(set);
    const Eigen::Isometry3d X_WA = mt::random_pose(rng, 1.2), X_WB = mt::random_pose(rng, 0.3);
    const Brute b = brute(set, X_WA, occupied, X_WB);
    INFO("scene " << scene << ", brute force " << b.min_signed);
    const double tol = 1e-12;

    const ms::TreeDistance sr = ms::signed_distance(tree, X_WA, rss, X_WB);
    const ms::TreeDistance sb = ms::signed_distance(tree, X_WA, box, X_WB);
    CHECK(sb.distance == sr.distance);
    CHECK(sb.distance == Approx(b.min_signed).margin(tol));

    const ms::TreeDistance dr = ms::distance(tree, X_WA, rss, X_WB);
    const ms::TreeDistance db = ms::distance(tree, X_WA, box, X_WB);
    if (b.min_signed > 0.0) {
      ++apart;
      CHECK(db.distance == dr.distance);
      CHECK(db.distance == Approx(b.min_signed).margin(tol));
    } else {
      ++overlapping;
      CHECK(db.distance <= 0.0);  // the first overlapping pair found
      CHECK(db.distance >= b.min_signed - tol);
    }

    ms::DistanceOptions capped;
    capped.upper_bound = std::max(0.0, b.min_signed) + 0.05;
    CHECK(ms::distance(tree, X_WA, box, X_WB, capped).found() ==
          ms::distance(tree, X_WA, rss, X_WB, capped).found());

    CHECK(ms::collide(tree, X_WA, box, X_WB) == (b.overlaps > 0));
    std::vector<ms::TreeContact> cr, cb;
    CHECK(ms::contacts(tree, X_WA, rss, X_WB, 1u << 20, cr) == b.overlaps);
    CHECK(ms::contacts(tree, X_WA, box, X_WB, 1u << 20, cb) == b.overlaps);
  }
  CHECK(apart > 5);
  CHECK(overlapping > 5);
}

TEST_CASE("A walk inside a target's answer keeps its own node stack",
          "[sphere_tree][query][target]") {
  std::mt19937 rng(52);
  const std::vector<bool> other_cells = random_cells(rng);
  const mt::CubeGridTarget other(kDepth, kHalf, other_cells, true);
  const ms::SphereTree probe(mt::random_sphere_set(rng, 12, 0.5, 0.02, 0.1));
  for (int scene = 0; scene < 20; ++scene) {
    const std::vector<bool> occupied = random_cells(rng);
    const mt::CubeGridTarget plain(kDepth, kHalf, occupied, true);
    const QueryingGrid querying(occupied, probe, other);
    const ms::SphereTree tree(mt::random_sphere_set(rng, 1 + rng() % 40, 0.5, 0.02, 0.15));
    const Eigen::Isometry3d X_WA = mt::random_pose(rng, 1.2), X_WB = mt::random_pose(rng, 0.3);
    const ms::TreeDistance a = ms::signed_distance(tree, X_WA, plain, X_WB);
    const ms::TreeDistance b = ms::signed_distance(tree, X_WA, querying, X_WB);
    CHECK(b.distance == a.distance);
    CHECK(b.sphere_a == a.sphere_a);
    CHECK(b.primitive_b == a.primitive_b);
    CHECK(b.stats.bv_tests == a.stats.bv_tests);
    CHECK(b.stats.leaf_tests == a.stats.leaf_tests);
  }
}
