#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <catch2/catch.hpp>

#include "medspheres/bake/bake.h"
#include "medspheres/bake/dilate.h"
#include "medspheres/error.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_tree.h"
#include "support/shared_meshes.h"
#include "support/temp_dir.h"

using namespace medspheres;
using Catch::Matchers::Contains;

namespace {

// Distance from p to the union, by brute force over the balls: an oracle independent
// of point_coverage's acceleration.
double outside_union(const std::vector<Sphere>& balls, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Sphere& b : balls) best = std::min(best, (p - b.center).norm() - b.radius);
  return std::max(best, 0.0);
}

struct Case {
  TriangleMesh mesh;
  SphereSet internal;
};

Case baked(TriangleMesh mesh, int resolution) {
  const MeshQuery q(mesh);
  BakeOptions o;
  o.resolution = resolution;
  SphereSet s = bake(q, o).spheres;
  return {std::move(mesh), std::move(s)};
}

const Case& knot() {
  static const Case c = baked(load_mesh(medspheres::test::example_mesh("knot1.off")).mesh, 24);
  return c;
}

const Case& capsule() {
  static const Case c = baked(make_capsule(0.3, 0.8, 32, 8), 20);
  return c;
}

bool bit_identical(const SphereSet& a, const SphereSet& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(a.spheres[i].center.data(), b.spheres[i].center.data(), 3 * sizeof(double)) !=
            0 ||
        std::memcmp(&a.spheres[i].radius, &b.spheres[i].radius, sizeof(double)) != 0)
      return false;
  return true;
}

}  // namespace

TEST_CASE("dilation never shrinks a sphere and keeps S_D first, in order", "[dilate]") {
  for (const Case* c : {&knot(), &capsule()}) {
    const MeshQuery q(c->mesh);
    const DilateResult d = dilate(q, c->internal);
    REQUIRE(d.spheres.size() >= c->internal.size());
    CHECK(d.spheres.size() == c->internal.size() + d.stats.added_vertex);
    std::size_t grown = 0;
    for (std::size_t i = 0; i < c->internal.size(); ++i) {
      CHECK(d.spheres.spheres[i].center == c->internal.spheres[i].center);
      CHECK(d.spheres.spheres[i].radius >= c->internal.spheres[i].radius);
      grown += d.spheres.spheres[i].radius > c->internal.spheres[i].radius;
    }
    CHECK(grown == d.stats.grown);
    CHECK(d.stats.v_points + d.stats.edge_points > 0);
  }
}

TEST_CASE("after dilation every mesh vertex is within the vertex tolerance", "[dilate]") {
  for (const Case* c : {&knot(), &capsule()}) {
    const MeshQuery q(c->mesh);
    for (double fraction : {0.0, 0.002}) {
      DilateOptions o;
      o.vertex_tolerance = fraction * c->mesh.bounds().sizes().maxCoeff();
      const DilateResult d = dilate(q, c->internal, o);
      const double tol = d.stats.vertex_tolerance;
      CHECK(tol > 0.0);
      // The undilated set misses some vertex by more than the tolerance, so the check
      // below is not vacuous.
      double before = 0.0;
      for (const Eigen::Vector3d& v : c->mesh.vertices)
        before = std::max(before, outside_union(c->internal.spheres, v));
      CHECK(before > tol);
      for (const Eigen::Vector3d& v : c->mesh.vertices)
        CHECK(outside_union(d.spheres.spheres, v) <= tol * (1 + 1e-12));
    }
  }
}

TEST_CASE("a dilated set is never farther from a copy of itself than S_D", "[dilate]") {
  const MeshQuery q(knot().mesh);
  const SphereSet plus = dilate(q, knot().internal).spheres;
  const SphereTree a(knot().internal), b(plus);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    X.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0;
    // distance() reports some overlapping pair when the sets overlap, so compare the
    // separation (0 when overlapping) and, for the overlapping case, the signed distance.
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    const double d_plus = distance(b, I, b, X).distance;
    const double d_sd = distance(a, I, a, X).distance;
    CHECK(std::max(d_plus, 0.0) <= std::max(d_sd, 0.0));
    CHECK(signed_distance(b, I, b, X).distance <= signed_distance(a, I, a, X).distance);
  }
}

TEST_CASE("the protrusion cap bounds how far any sphere sticks out", "[dilate]") {
  const MeshQuery q(knot().mesh);
  const double L = knot().mesh.bounds().sizes().maxCoeff();
  const DilateResult free = dilate(q, knot().internal);
  DilateOptions o;
  o.max_protrusion = 0.002 * L;
  const DilateResult capped = dilate(q, knot().internal, o);
  const VolumeError unc = FitEvaluator(knot().mesh).volume_error(free.spheres.spheres);
  const VolumeError cap = FitEvaluator(knot().mesh).volume_error(capped.spheres.spheres);
  CHECK(unc.max_protrusion > o.max_protrusion);  // the cap has something to do
  CHECK(cap.max_protrusion <= o.max_protrusion * (1 + 1e-9) + 1e-12 * L);
  // Vertices are still covered within the tolerance.
  for (const Eigen::Vector3d& v : knot().mesh.vertices)
    CHECK(outside_union(capped.spheres.spheres, v) <= capped.stats.vertex_tolerance * (1 + 1e-12));
}

TEST_CASE("cover rounds bring every sample of the last round within the tolerance", "[dilate]") {
  const MeshQuery q(knot().mesh);
  DilateOptions o;
  o.cover_tolerance = 0.002 * knot().mesh.bounds().sizes().maxCoeff();
  o.cover_samples = 5000;
  o.cover_max_rounds = 64;
  const DilateResult d = dilate(q, knot().internal, o);
  REQUIRE(d.stats.cover_reached);
  CHECK(d.stats.cover_rounds >= 1);  // the rounds had work to do
  CHECK(d.stats.added_cover > 0);
  CHECK(d.stats.uncovered_max <= o.cover_tolerance);
  // Re-draw the last round's samples (seed + 1 + round) and check them independently.
  const SurfaceSamples s = sample_surface(
      knot().mesh, o.cover_samples, o.seed + 1 + static_cast<std::uint64_t>(d.stats.cover_rounds));
  double worst = 0.0;
  for (const Eigen::Vector3d& p : s.points)
    worst = std::max(worst, outside_union(d.spheres.spheres, p));
  CHECK(worst <= o.cover_tolerance);
  CHECK(worst == Approx(d.stats.uncovered_max).margin(1e-12));
}

TEST_CASE("dilation is deterministic for a seed, whatever the thread count", "[dilate]") {
  const MeshQuery q(knot().mesh);
  DilateOptions o;
  o.cover_tolerance = 0.004 * knot().mesh.bounds().sizes().maxCoeff();
  o.threads = 1;
  const DilateResult one = dilate(q, knot().internal, o);
  for (int threads : {2, 3}) {
    o.threads = threads;
    CHECK(bit_identical(one.spheres, dilate(q, knot().internal, o).spheres));
  }
  o.threads = 0;
  o.seed = 99;
  const DilateResult other = dilate(q, knot().internal, o);
  CHECK(other.stats.edge_points == one.stats.edge_points);

  // Under a protrusion cap many small spheres are added, their candidates made in
  // parallel batches of 64: still the same spheres for every thread count.
  DilateOptions capped;
  capped.max_protrusion = 0.0002 * knot().mesh.bounds().sizes().maxCoeff();
  capped.threads = 1;
  const DilateResult serial = dilate(q, knot().internal, capped);
  INFO("added at vertices: " << serial.stats.added_vertex);
  CHECK(serial.stats.added_vertex > 3 * 64);
  for (int threads : {2, 3}) {
    capped.threads = threads;
    CHECK(bit_identical(serial.spheres, dilate(q, knot().internal, capped).spheres));
  }
}

TEST_CASE("dilation rejects bad input by name", "[dilate]") {
  const MeshQuery q(capsule().mesh);
  auto with = [](auto set) {
    DilateOptions o;
    set(o);
    return o;
  };
  CHECK_THROWS_WITH(dilate(q, SphereSet{}), Contains("sphere set"));
  SphereSet bad = capsule().internal;
  bad.spheres[0].radius = -1.0;
  CHECK_THROWS_AS(dilate(q, bad), InputError);
  CHECK_THROWS_WITH(
      dilate(q, capsule().internal, with([](DilateOptions& o) { o.vertex_tolerance = -1; })),
      Contains("vertex tolerance"));
  CHECK_THROWS_WITH(
      dilate(q, capsule().internal, with([](DilateOptions& o) { o.max_protrusion = -1; })),
      Contains("protrusion"));
  CHECK_THROWS_WITH(dilate(q, capsule().internal, with([](DilateOptions& o) {
                             o.cover_tolerance = 0.1;
                             o.cover_samples = 0;
                           })),
                    Contains("cover samples"));
  CHECK_THROWS_WITH(dilate(q, capsule().internal, with([](DilateOptions& o) { o.threads = -2; })),
                    Contains("threads"));
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("dilation covers every vertex of every closed classic shared mesh", "[dilate][shared]") {
  for (const auto& row : test::shared_meshes()) {
    if (!row.closed || !row.classic()) continue;
    INFO(row.file);
    const Case c = baked(load_mesh(row.path).mesh, 24);
    const MeshQuery q(c.mesh);
    const DilateResult d = dilate(q, c.internal);
    const std::vector<PointCoverage> cov = point_coverage(d.spheres.spheres, c.mesh.vertices);
    double worst = 0.0;
    for (const PointCoverage& p : cov) worst = std::max(worst, p.outside);
    CHECK(worst <= d.stats.vertex_tolerance * (1 + 1e-12));
  }
}
#endif
