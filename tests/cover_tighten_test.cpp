// tighten_cover: a caller's own balls made into a certified cover. The oracles: sampled
// surface coverage (fit_metrics), and the stats against a Monte-Carlo union volume and
// brute-force protrusions (support/cover_oracles.h); the comparisons between sets use the
// exact union volume (union_volume.h) and the protrusions (sphere_protrusions).
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/bake/cover_record.h"
#include "medspheres/cover/cover.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_query.h"
#include "support/cover_oracles.h"
#include "support/cover_solids.h"

using namespace medspheres;

namespace {

using test::sampled_gap;

double largest_protrusion(const MeshQuery& query, const std::vector<Sphere>& balls) {
  const std::vector<double> p = sphere_protrusions(query, balls, 1);
  return *std::max_element(p.begin(), p.end());
}

// A planner-like set: \p k balls at seeded points inside the solid, each as large as its
// depth times 1.3 (so some stick out and parts of the surface are missed).
std::vector<Sphere> planner_like(const MeshQuery& query, std::size_t k, unsigned seed) {
  const Eigen::AlignedBox3d box = query.mesh().bounds();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Sphere> balls;
  while (balls.size() < k) {
    const Eigen::Vector3d p =
        box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    if (!query.inside(p)) continue;
    balls.push_back({p, 1.3 * query.closest_point(p).distance()});
  }
  return balls;
}

}  // namespace

TEST_CASE("tighten_cover: a set that misses the surface becomes a certified cover",
          "[cover][tighten]") {
  for (const test::NamedSolid& solid : test::cover_solids()) {
    const MeshQuery query(solid.mesh);
    for (std::size_t k : {1, 3, 8, 20}) {
      CAPTURE(solid.name, k);
      const std::vector<Sphere> start = planner_like(query, k, 7);
      REQUIRE(sampled_gap(solid.mesh, start) > 0.0);  // the start does not cover
      const CoverResult r = tighten_cover(query, start);
      CHECK(r.stats.certified);
      CHECK(r.certificate.certified);
      CHECK(r.spheres.size() >= 1);
      CHECK(r.spheres.size() <= k);
      CHECK(r.stats.start_spheres == k);
      // Every element held by its ball: the certificate needs no repair.
      CHECK(r.stats.repaired == 0);
      CHECK(r.stats.interior_points == 0);
      CHECK(sampled_gap(solid.mesh, r.spheres.spheres) == 0.0);
      const test::SampledVolume u = test::sampled_union_volume(r.spheres.spheres, 40000, 5);
      CHECK(std::abs(r.stats.union_volume - u.value) <= 4 * u.sigma);
      CHECK(r.stats.max_protrusion ==
            Approx(test::brute_max_protrusion(solid.mesh, r.spheres.spheres)).margin(1e-9));
    }
  }
}

TEST_CASE("tighten_cover never loosens a set that already covers", "[cover][tighten]") {
  // The start: eight balls, each the circumscribed ball of an octant of the solid's box, a
  // loose cover. Each ball can only shrink (every element is already held), and the descent
  // only lowers the union; so the union and the largest protrusion stay at most the
  // start's, up to the slack of step 5 (1e-9 L per radius).
  for (const test::NamedSolid& solid : test::cover_solids()) {
    CAPTURE(solid.name);
    const MeshQuery query(solid.mesh);
    const Eigen::AlignedBox3d box = solid.mesh.bounds();
    const Eigen::Vector3d half = 0.5 * box.sizes();
    std::vector<Sphere> start;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d c =
          box.min() + 0.5 * half +
          Eigen::Vector3d(corner & 1 ? half.x() : 0.0, corner & 2 ? half.y() : 0.0,
                          corner & 4 ? half.z() : 0.0);
      start.push_back({c, 0.5 * half.norm() * (1.0 + 1e-9)});
    }
    REQUIRE(sampled_gap(solid.mesh, start) == 0.0);
    const double L = box.sizes().maxCoeff();
    const CoverResult r = tighten_cover(query, start);
    CHECK(r.stats.certified);
    CHECK(r.stats.repaired == 0);
    const double before = measure_union(start).volume;
    CHECK(r.stats.union_volume <= before * (1.0 + 1e-8));
    // The octant balls are the box's own minimum balls; round solids leave them room.
    if (solid.name != "box") CHECK(r.stats.union_volume < 0.95 * before);
    CHECK(largest_protrusion(query, r.spheres.spheres) <=
          largest_protrusion(query, start) + 1e-8 * L);
  }
}

TEST_CASE("tighten_cover: the same spheres for every thread count", "[cover][tighten]") {
  const MeshQuery query(make_torus(1.0, 0.3, 32, 12));
  const std::vector<Sphere> start = planner_like(query, 12, 3);
  CoverOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const CoverResult a = tighten_cover(query, start, one), b = tighten_cover(query, start, two);
  test::check_same_spheres(a.spheres.spheres, b.spheres.spheres);
}

TEST_CASE("tighten_cover: the record says the cover was tightened from the start",
          "[cover][tighten]") {
  const TriangleMesh mesh = make_capsule(0.3, 0.8, 24, 6);
  const MeshQuery query(mesh);
  const CoverResult r = tighten_cover(query, planner_like(query, 6, 11));
  MeshProvenance source;
  source.mesh = "capsule.obj";
  const nlohmann::json j = nlohmann::json::parse(cover_metadata_json(cover_bake_record(source, r)));
  CHECK(j["generator"]["params"]["mode"] == "cover_tighten");
  CHECK(j["generator"]["params"]["budget"] == 6.0);
  CHECK(j["stats"]["certified"] == true);
}

TEST_CASE("tighten_cover rejects a start it cannot use, naming the sphere", "[cover][tighten]") {
  const MeshQuery query(make_icosphere(1.0, 1));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(tighten_cover(query, {}), Catch::Contains("start: no spheres"));
  CHECK_THROWS_AS(
      tighten_cover(query, {{Eigen::Vector3d::Zero(), 0.5}, {Eigen::Vector3d::Zero(), -1.0}}),
      std::invalid_argument);
  CHECK_THROWS_WITH(
      tighten_cover(query, {{Eigen::Vector3d::Zero(), 0.5}, {Eigen::Vector3d(nan, 0, 0), 1.0}}),
      Catch::Contains("sphere 1"));
  CHECK(cover_start_problem({{Eigen::Vector3d::Zero(), 0.0}}).empty());  // a point grows
}
