// OctreeCells (medspheres/fcl/octree_cells.h) against FCL's own query of a mesh and an
// fcl::OcTree: the same verdict at the margin and the same distance within it, over seeded
// poses of a capsule link around a rotated octree whose pruned leaves are larger cells, and
// at poses bisected to 1e-4 m of the margin.

#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include <fcl/fcl.h>
#include <octomap/octomap.h>
#include <catch2/catch.hpp>

#include "medspheres/fcl/octree_cells.h"
#include "support/check_fixtures.h"
#include "support/fcl_fixtures.h"

using namespace medspheres;
namespace mf = medspheres::fcl;

namespace {

// A noisy slab of points and a solid block, which octomap prunes into larger cells.
std::shared_ptr<octomap::OcTree> cloud() {
  auto tree = std::make_shared<octomap::OcTree>(0.02);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 600; ++i)
    tree->updateNode(
        octomap::point3d(float(0.4 * u(rng)), float(0.3 * u(rng)), float(0.05 * u(rng))), true);
  for (int x = 0; x < 16; ++x)
    for (int y = 0; y < 16; ++y)
      for (int z = 0; z < 16; ++z)
        tree->updateNode(octomap::point3d(float(0.0805 + 0.01 * x), float(0.0405 + 0.01 * y),
                                          float(0.1605 + 0.01 * z)),
                         true);
  tree->updateInnerOccupancy();
  tree->prune();
  return tree;
}

// FCL's distance of the mesh and the octree, pruned at the margin as the fallback asks it.
double fcl_distance(const mf::MeshModel& mesh, const Eigen::Isometry3d& X_WA,
                    const ::fcl::OcTreed& tree, const Eigen::Isometry3d& X_WO, double margin) {
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  result.min_distance = std::nextafter(margin, std::numeric_limits<double>::infinity());
  return ::fcl::distance(&mesh, X_WA, &tree, X_WO, request, result);
}

struct Fixture {
  std::shared_ptr<octomap::OcTree> tree = cloud();
  ::fcl::OcTreed octree{tree};
  Eigen::Isometry3d X_WO = test::pose_of({0.1, -0.2, 0.3}, 0.3, -0.2, 0.7);
  mf::OctreeCells cells{octree, X_WO};
  test::CapsuleLink link = test::capsule_arm_links()[2];
  std::shared_ptr<const mf::MeshModel> mesh =
      test::make_bvh<::fcl::OBBRSSd>(test::capsule_link_mesh(link));
  // The link with its closed-form certified cover, and the same mesh without a cover.
  mf::OctreeCells::Link covered = make_link(true), bare = make_link(false);

  mf::OctreeCells::Link make_link(bool certified) const {
    SphereSet outer = test::capsule_set(link, 6, true);
    outer.metadata_json = certified ? R"({"certified": true})" : "{}";
    mf::BoundedGeometryOptions options;
    options.allow_uncertified = !certified;
    return mf::OctreeCells::Link(
        mf::BoundedGeometry(link.name, test::capsule_set(link, 6, false), outer, mesh, options));
  }
};

// Compares both links' answers with FCL's at X_WA; returns FCL's.
double compare(const Fixture& f, const Eigen::Isometry3d& X_WA, double margin) {
  const double exact = fcl_distance(*f.mesh, X_WA, f.octree, f.X_WO, margin);
  for (const mf::OctreeCells::Link* l : {&f.covered, &f.bare}) {
    const double d = f.cells.distance(*l, X_WA, margin);
    CHECK((d <= margin) == (exact <= margin));
    if (exact > 0.0 && exact <= margin) CHECK(d == Approx(exact).margin(1e-12));
    if (exact <= 0.0) CHECK(d <= 0.0);
  }
  return exact;
}

Eigen::Isometry3d random_pose(std::mt19937& rng, const Eigen::Isometry3d& X_WO) {
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::Isometry3d X_OA = Eigen::Isometry3d::Identity();
  X_OA.linear() = Eigen::Quaterniond(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)
                      .normalized()
                      .toRotationMatrix();
  X_OA.translation() =
      Eigen::Vector3d(-0.15 + 0.7 * u(rng), -0.15 + 0.6 * u(rng), -0.15 + 0.6 * u(rng));
  return X_WO * X_OA;
}

}  // namespace

TEST_CASE("octree cells: FCL's cells, pruned leaves as larger cubes", "[check][fcl]") {
  const Fixture f;
  std::size_t leaves = 0, larger = 0;
  for (auto it = f.tree->begin_leafs(); it != f.tree->end_leafs(); ++it) {
    if (!f.octree.isNodeOccupied(&*it)) continue;
    ++leaves;
    larger += it.getDepth() < f.tree->getTreeDepth();
  }
  CHECK(f.cells.size() == leaves);
  CHECK(larger > 0);
  // Each cell is a cube of the octree's leaf sizes.
  for (std::size_t i = 0; i < f.cells.size(); ++i) {
    const double side = f.cells.cell(i).width();
    CHECK(side == Approx(f.cells.cell(i).depth()));
    CHECK(std::abs(std::log2(side / 0.02) - std::round(std::log2(side / 0.02))) < 1e-9);
  }
}

TEST_CASE("octree cells: FCL's verdict and distance at seeded poses and near the margin",
          "[check][fcl]") {
  const Fixture f;
  std::mt19937 rng(17);
  const double margin = 0.01;
  std::size_t colliding = 0, free = 0, near = 0;
  std::vector<Eigen::Isometry3d> hits;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Isometry3d X = random_pose(rng, f.X_WO);
    const double exact = compare(f, X, margin);
    colliding += exact <= margin;
    free += exact > margin;
    if (exact <= margin) hits.push_back(X);
    near += exact > margin && fcl_distance(*f.mesh, X, f.octree, f.X_WO, 2 * margin) <= 2 * margin;
  }
  CHECK(colliding >= 20);
  CHECK(free >= 20);
  CHECK(near >= 5);
  // From colliding poses outward along a seeded direction, to the pose where FCL's verdict
  // turns, then 1e-4 m to either side of it: the cover's pruning is tested at its edge.
  std::normal_distribution<double> g;
  std::size_t bisected = 0;
  for (std::size_t k = 0; k < hits.size() && bisected < 25; ++k) {
    const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    auto at = [&](double t) {
      Eigen::Isometry3d X = hits[k];
      X.translation() += t * dir;
      return X;
    };
    double lo = 0.0, hi = 0.4;
    if (fcl_distance(*f.mesh, at(hi), f.octree, f.X_WO, margin) <= margin) continue;
    while (hi - lo > 1e-6) {
      const double mid = 0.5 * (lo + hi);
      (fcl_distance(*f.mesh, at(mid), f.octree, f.X_WO, margin) <= margin ? lo : hi) = mid;
    }
    for (double t : {lo - 1e-4, lo, hi, hi + 1e-4}) compare(f, at(t), margin);
    compare(f, hits[k], 0.0);
    ++bisected;
  }
  CHECK(bisected >= 10);
}

TEST_CASE("octree cells: a link without a mesh, a bad margin and a bad pose are refused",
          "[check][fcl]") {
  const Fixture f;
  CHECK_THROWS_AS(f.cells.distance(f.covered, f.X_WO, -1.0), std::invalid_argument);
  CHECK_THROWS_AS(f.cells.distance(f.covered, f.X_WO, std::nan("")), std::invalid_argument);
  Eigen::Isometry3d bad = f.X_WO;
  bad.translation().x() = std::nan("");
  CHECK_THROWS_AS(f.cells.distance(f.covered, bad, 0.01), std::invalid_argument);
  const SphereSet inner = test::capsule_set(f.link, 4, false);
  SphereSet outer = test::capsule_set(f.link, 4, true);
  outer.metadata_json = R"({"certified": true})";
  CHECK_THROWS_AS(mf::OctreeCells::Link(mf::BoundedGeometry("l2", inner, outer)),
                  std::invalid_argument);
}
