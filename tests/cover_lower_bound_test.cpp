#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/cover/cover.h"
#include "medspheres/cover/cover_lower_bound.h"
#include "medspheres/error.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "support/sanitizer_build.h"

using namespace medspheres;

namespace {

double largest_side(const TriangleMesh& mesh) {
  return mesh.bounds().sizes().maxCoeff();
}

double max_protrusion(const MeshQuery& query, const std::vector<Sphere>& balls) {
  const std::vector<double> p = sphere_protrusions(query, balls, 2);
  return *std::max_element(p.begin(), p.end());
}

// The signed distance D (positive inside) as protrusions measure it (fit_metrics.h).
double depth(const MeshQuery& query, const Eigen::Vector3d& c) {
  const double d = query.closest_point(c).distance();
  return query.inside(c) ? d : -d;
}

// K balls on the axis of the box with half extents (a, b, b), a >> b, each holding a slab
// of length 2a / K: centre on the axis, radius to the slab's corners (plus a margin).
std::vector<Sphere> axis_cover(double a, double b, std::size_t K) {
  std::vector<Sphere> balls;
  const double half = a / static_cast<double>(K);
  for (std::size_t i = 0; i < K; ++i) {
    const double x = -a + (2.0 * static_cast<double>(i) + 1.0) * half;
    balls.push_back({Eigen::Vector3d(x, 0, 0), std::sqrt(half * half + 2 * b * b) * (1 + 1e-9)});
  }
  return balls;
}

// The options before the defaults rose (cover_lower_bound.h): a valid bound for a fraction
// of the defaults' CPU. These tests check validity against closed forms and brute force;
// how tight the defaults are is bench_budget's figure. Two threads.
// Settings that the closed forms' checks need in every build.
CoverLowerBoundOptions settled() {
  CoverLowerBoundOptions o;
  o.resolution = 48;
  o.count_queries = 50000;
  o.count_passes = 3;
  o.threads = 2;
  return o;
}

// settled(), with a coarser grid and fewer boxes in the sanitizer builds, where the same steps
// run about five times slower: every step of the bound still runs, on fewer cells.
CoverLowerBoundOptions quick() {
  CoverLowerBoundOptions o = settled();
  if (test::kSanitizerBuild) {
    o.resolution = 32;
    o.count_queries = 20000;
  }
  return o;
}

}  // namespace

TEST_CASE("cover lower bound: below the one-ball cover of a sphere", "[cover_lower_bound]") {
  // The icosphere's vertices lie on the unit sphere, so the unit ball at the origin covers it
  // and protrudes by 1 - D(0), D(0) its inradius: the least protrusion of one ball is at most
  // that (it is that, up to the grid).
  const TriangleMesh mesh = make_icosphere(1.0, 3);
  const MeshQuery query(mesh);
  const std::vector<Sphere> ball{{Eigen::Vector3d::Zero(), 1.0 + 1e-12}};
  REQUIRE(certify_cover(mesh, ball).certified);
  const double truth = max_protrusion(query, ball);
  const CoverLowerBound b = cover_protrusion_lower_bound(query, 1, quick());
  INFO("bound " << b.bound << " one ball " << truth);
  CHECK(b.bound >= 0.9 * truth);  // two antipodal witnesses: a ball holding both is as wide
  CHECK(b.bound <= truth + 1e-9);
  CHECK(b.witnesses.size() == 2);
  CHECK(b.closed);
}

TEST_CASE("cover lower bound: a long thin box between closed forms", "[cover_lower_bound]") {
  // Box [-2, 2] x [-0.1, 0.1]^2. Any K balls covering it: K + 1 points along an edge at
  // spacing 4 / K put two in one ball, of radius >= 2 / K, whose centre is at most 0.1 deep:
  // protrusion >= 2 / K - 0.1 (a closed form by the same pigeonhole, with the exact depth).
  // The hand cover of K axis balls achieves sqrt((2 / K)^2 + 0.02) - 0.1.
  const double a = 2.0, b = 0.1;
  const TriangleMesh mesh = make_box(Eigen::Vector3d(a, b, b), 4);
  const MeshQuery query(mesh);
  // Two of the four budgets in the sanitizer builds.
  for (const std::size_t K : test::budgets({1, 2, 4, 8}, {1, 8})) {
    INFO("K = " << K);
    const std::vector<Sphere> hand = axis_cover(a, b, K);
    REQUIRE(certify_cover(mesh, hand).certified);
    const double achieved = max_protrusion(query, hand);
    const CoverLowerBound lb = cover_protrusion_lower_bound(query, K, quick());
    const double closed_form = 2.0 / static_cast<double>(K) - b;
    INFO("bound " << lb.bound << " closed form " << closed_form << " hand cover " << achieved
                  << " cell reach " << lb.cell_reach);
    CHECK(lb.bound <= achieved + 1e-9);
    CHECK(lb.bound > 0.0);
    // Not vacuous: the refined pairs reach the closed form, less half a grid cell.
    CHECK(lb.bound >= closed_form - 0.5 * lb.cell_reach);
    CHECK(lb.witnesses.size() == K + 1);
  }
}

TEST_CASE("cover lower bound: never above a certified bake_cover", "[cover_lower_bound]") {
  std::vector<std::pair<std::string, TriangleMesh>> solids = {
      {"box", make_box(Eigen::Vector3d(1.0, 0.6, 0.3), 2)},
      {"capsule", make_capsule(0.3, 0.8, 24, 6)},
      {"torus", make_torus(1.0, 0.3, 32, 12)},
      {"cylinder", make_cylinder(0.2, 1.0, 24)}};
  solids.emplace_back(
      "eight.off", load_mesh(std::string(MEDSPHERES_SOURCE_DIR) + "/examples/data/eight.off").mesh);
  for (const auto& [name, raw] : solids) {
    const FitEvaluator fit(raw, 2);  // oriented, as protrusions are measured
    REQUIRE(fit.volume());
    const double L = largest_side(fit.query().mesh());
    // Two budgets of the five in the sanitizer builds, where a bake costs ten times more.
    for (const std::size_t K : test::budgets({1, 2, 4, 8, 16}, {2, 16})) {
      INFO(name << " K = " << K);
      CoverOptions co;
      co.threads = 2;
      const CoverResult cover = bake_cover(fit.query(), K, co);
      REQUIRE(cover.stats.certified);
      CoverLowerBoundOptions lo = quick();
      // Any budget and witnesses give a valid bound; these are cheap. The sanitizer builds
      // run the pair argument alone here: the counting argument's weights took most of this
      // test's time there, and its other tests run it under the sanitizers.
      lo.count_queries = test::kSanitizerBuild ? 0 : 5000;
      lo.count_witnesses = 256;
      const CoverLowerBound lb = cover_protrusion_lower_bound(fit.query(), K, lo);
      INFO("bound " << lb.bound / L << " L, cover " << cover.stats.max_protrusion / L << " L");
      CHECK(lb.bound <= cover.stats.max_protrusion);
      CHECK(lb.bound <= max_protrusion(fit.query(), cover.spheres.spheres));
    }
  }
}

TEST_CASE("cover lower bound: no ball holding two witnesses protrudes less (sampled)",
          "[cover_lower_bound]") {
  // Brute force on the claim behind the pair argument's bound: a ball holding witnesses x and
  // y has radius >= max(|c - x|, |c - y|), so it protrudes by >= max(|c - x|, |c - y|) - D(c)
  // at every centre c. The least of that over 20000 random centres must not fall below it.
  const TriangleMesh mesh = make_capsule(0.3, 0.8, 24, 6);
  const MeshQuery query(mesh);
  const CoverLowerBound lb = cover_protrusion_lower_bound(query, 3, quick());
  REQUIRE(lb.witnesses.size() == 4);
  REQUIRE(lb.pair_bound > 0.0);
  std::mt19937_64 rng(7);
  const Eigen::AlignedBox3d box = mesh.bounds();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double least = std::numeric_limits<double>::infinity();
  for (int s = 0; s < 20000; ++s) {
    const Eigen::Vector3d c =
        box.min() + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(box.sizes());
    const double D = depth(query, c);
    for (std::size_t i = 0; i < lb.witnesses.size(); ++i)
      for (std::size_t j = i + 1; j < lb.witnesses.size(); ++j)
        least = std::min(least,
                         std::max((c - lb.witnesses[i]).norm(), (c - lb.witnesses[j]).norm()) - D);
  }
  // `bound` may be the counting argument's, which these witnesses do not carry.
  INFO("pair bound " << lb.pair_bound << " sampled least " << least);
  CHECK(least >= lb.pair_bound);
  for (const Eigen::Vector3d& w : lb.witnesses)
    CHECK(query.closest_point(w).distance() <= 1e-9 * largest_side(mesh));
}

TEST_CASE("cover lower bound: the counting argument on a thin plate, between closed forms",
          "[cover_lower_bound]") {
  // Plate [-1, 1]^2 x [-0.05, 0.05]. A ball of protrusion t has r <= t + D(c), and D(c) <=
  // 0.05 - |z| inside, so it holds at most 2 pi (t^2 + 0.1 t) of the two faces' area 8 (a
  // disk of radius^2 r^2 - (0.05 -+ z)^2 on each; less outside): K balls need
  // 2 pi K (t^2 + 0.1 t) >= 8, the area bound t*. The hand cover: a 4 x 4 grid of balls,
  // each through the corners of its 0.5 x 0.5 x 0.1 block, protrudes by sqrt(0.125 +
  // 0.0025) - 0.05. The counting bound must lie between, and reach most of t*.
  const double b = 0.05;
  const TriangleMesh mesh = make_box(Eigen::Vector3d(1.0, 1.0, b), 8);
  const MeshQuery query(mesh);
  const std::size_t K = 16;
  std::vector<Sphere> hand;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      hand.push_back({Eigen::Vector3d(-0.75 + 0.5 * i, -0.75 + 0.5 * j, 0.0),
                      std::sqrt(0.125 + b * b) * (1 + 1e-9)});
  REQUIRE(certify_cover(mesh, hand).certified);
  const double achieved = max_protrusion(query, hand);
  const double area_bound =
      0.5 * (-2 * b + std::sqrt(4 * b * b + 4 * 8.0 / (2 * M_PI * static_cast<double>(K))));
  CoverLowerBoundOptions o = settled();
  const CoverLowerBound lb = cover_protrusion_lower_bound(query, K, o);
  o.count_queries = 0;
  const CoverLowerBound pairs = cover_protrusion_lower_bound(query, K, o);
  INFO("bound " << lb.bound << " (pairs " << lb.pair_bound << ", counting " << lb.count_bound
                << ") area bound " << area_bound << " hand cover " << achieved);
  CHECK(area_bound < achieved);  // the closed forms themselves
  CHECK(lb.bound <= achieved);
  CHECK(lb.pair_bound == pairs.bound);  // the pair argument is untouched
  CHECK(lb.bound >= pairs.bound);
  CHECK(lb.count_bound >= 0.75 * area_bound);
  CHECK(lb.count_points.size() > K + 1);
}

TEST_CASE("cover lower bound: counting proves more than pairs on a torus at K = 16",
          "[cover_lower_bound]") {
  // Where one ball can straddle the tube, pairs of witnesses prove little; a K-th of the
  // surface held by one ball proves more. Both stay below a certified cover.
  const FitEvaluator fit(make_torus(1.0, 0.3, 32, 12), 2);
  const std::size_t K = 16;
  CoverLowerBoundOptions o = quick();
  // quick()'s coarse depth grid, where the pair argument is weak (at the default 128 it
  // proves 0.043 against the counting argument's 0.051).
  const CoverLowerBound lb = cover_protrusion_lower_bound(fit.query(), K, o);
  CoverOptions co;
  co.threads = 2;
  const CoverResult cover = bake_cover(fit.query(), K, co);
  REQUIRE(cover.stats.certified);
  INFO("pairs " << lb.pair_bound << " counting " << lb.count_bound << " cover "
                << cover.stats.max_protrusion);
  CHECK(lb.count_bound > 1.5 * lb.pair_bound);
  CHECK(lb.bound == std::max(lb.pair_bound, lb.count_bound));
  CHECK(lb.bound <= max_protrusion(fit.query(), cover.spheres.spheres));
}

TEST_CASE("cover lower bound: one ball covers a sphere, so no K proves more",
          "[cover_lower_bound]") {
  // Any K >= 1 may use a single ball: the unit ball at the origin covers the icosphere, so
  // every bound is at most its protrusion 1 - D(0), however many witnesses are counted.
  const TriangleMesh mesh = make_icosphere(1.0, 3);
  const MeshQuery query(mesh);
  const std::vector<Sphere> ball{{Eigen::Vector3d::Zero(), 1.0 + 1e-12}};
  const double truth = max_protrusion(query, ball);
  CoverLowerBoundOptions o = quick();
  o.count_queries = 10000;
  o.count_witnesses = 256;
  // Two of the three budgets in the sanitizer builds.
  for (const std::size_t K : test::budgets({2, 8, 32}, {2, 32})) {
    const CoverLowerBound lb = cover_protrusion_lower_bound(query, K, o);
    INFO("K = " << K << " bound " << lb.bound << " counting " << lb.count_bound << " one ball "
                << truth);
    if (K == 2) CHECK(lb.count_bound > 0.5 * truth);  // the counting argument proves much
    CHECK(lb.bound <= truth + 1e-9);
  }
}

TEST_CASE("cover lower bound: no ball holding a K-th of the weight protrudes less (sampled)",
          "[cover_lower_bound]") {
  // Brute force on the counting claim: at every centre c, a ball holding weight >= ceil(Y /
  // K) of the counted witnesses has radius >= d_y(c), so it protrudes by >= d_y(c) - D(c).
  // The least of that over random centres, and over centres near the witnesses and deep
  // inside, must not fall below the counting bound.
  const TriangleMesh mesh = make_torus(1.0, 0.3, 32, 12);
  const MeshQuery query(mesh);
  const std::size_t K = 12;
  CoverLowerBoundOptions o = quick();
  o.count_passes = CoverLowerBoundOptions{}.count_passes;  // the default's later passes too
  const CoverLowerBound lb = cover_protrusion_lower_bound(query, K, o);
  REQUIRE(lb.count_bound > 0.0);
  REQUIRE(lb.count_points.size() == lb.count_weights.size());
  long total = 0;
  for (long w : lb.count_weights) total += w;
  const long need = (total + static_cast<long>(K) - 1) / static_cast<long>(K);
  const auto reach = [&](const Eigen::Vector3d& c) {
    std::vector<std::pair<double, long>> d;
    for (std::size_t i = 0; i < lb.count_points.size(); ++i)
      d.emplace_back((c - lb.count_points[i]).norm(), lb.count_weights[i]);
    std::sort(d.begin(), d.end());
    long held = 0;
    for (const auto& [r, w] : d)
      if ((held += w) >= need) return r;
    return std::numeric_limits<double>::infinity();
  };
  std::mt19937_64 rng(11);
  const Eigen::AlignedBox3d box = mesh.bounds();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> jitter(0.0, 0.05);
  double least = std::numeric_limits<double>::infinity();
  for (int s = 0; s < 6000; ++s) {
    Eigen::Vector3d c =
        box.min() + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(box.sizes());
    if (s % 2 == 1) {  // on the torus's core circle, where balls are deepest
      const double a = 2 * M_PI * u(rng);
      c = Eigen::Vector3d(std::cos(a), std::sin(a), 0.0) +
          Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    }
    least = std::min(least, reach(c) - depth(query, c));
  }
  INFO("counting bound " << lb.count_bound << " sampled least " << least);
  CHECK(least >= lb.count_bound);
  for (const Eigen::Vector3d& w : lb.count_points)
    CHECK(query.closest_point(w).distance() <= 1e-9 * largest_side(mesh));
}

TEST_CASE("cover lower bound: an open mesh's winding solid, on request", "[cover_lower_bound]") {
  TriangleMesh open = make_box(Eigen::Vector3d(1.0, 0.4, 0.2), 3);
  open.triangles.pop_back();  // a hole of one triangle
  MeshQueryOptions caps;
  caps.cap_holes = true;  // protrusions of an open mesh are measured with the holes capped
  const MeshQuery query(open, caps);
  CHECK_THROWS_AS(cover_protrusion_lower_bound(query, 4), InputError);
  CoverLowerBoundOptions o = quick();
  o.winding_solid = true;
  o.count_queries = 5000;
  o.count_witnesses = 256;
  for (std::size_t K : {1, 4, 8}) {
    INFO("K = " << K);
    const CoverLowerBound lb = cover_protrusion_lower_bound(query, K, o);
    CHECK_FALSE(lb.closed);
    const CoverResult cover = bake_cover(query, K);
    REQUIRE(cover.stats.certified);
    INFO("bound " << lb.bound << " cover " << cover.stats.max_protrusion);
    CHECK(lb.bound > 0.0);
    CHECK(lb.bound <= max_protrusion(query, cover.spheres.spheres));
  }
}

TEST_CASE("cover lower bound: a flat open square", "[cover_lower_bound]") {
  // No volume at all: the bound must stay finite, and below the protrusion of the ball on
  // the square's centre through its corners (radius sqrt(2), centre on the surface).
  TriangleMesh square;
  square.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  MeshQueryOptions caps;
  caps.cap_holes = true;
  const MeshQuery query(square, caps);
  CoverLowerBoundOptions o = quick();
  o.winding_solid = true;
  const std::vector<Sphere> ball{{Eigen::Vector3d::Zero(), std::sqrt(2.0) * (1 + 1e-12)}};
  const double one_ball = max_protrusion(query, ball);
  for (std::size_t K : {1, 3}) {
    const CoverLowerBound lb = cover_protrusion_lower_bound(query, K, o);
    INFO("K = " << K << " bound " << lb.bound << " one ball " << one_ball);
    CHECK(std::isfinite(lb.bound));
    if (K == 1) CHECK(lb.bound >= 0.9 * one_ball);  // two far corners: as wide as the ball
    CHECK(lb.bound <= one_ball);
  }
}

TEST_CASE("cover lower bound: evenly weighed witnesses on a torus at K = 32",
          "[cover_lower_bound]") {
  // The best K-ball cover of a torus is close to a ring of balls on its axis, each holding
  // a slice of equal angle. With 1024 chosen witnesses a ball can hold a K-th of their
  // weight with a slice narrower than a K-th of the surface; 8192 points of weight 1
  // measure the surface itself. The bound must rise, stay below the ring, and not depend
  // on the thread count (8192 points sample 65536: the farthest-point passes run split).
  const int segments = 64;
  const std::size_t K = 32;
  const TriangleMesh mesh = make_torus(1.0, 0.25, segments, 16);
  const MeshQuery query(mesh);
  std::vector<Sphere> ring;  // ball j holds the vertex rings 2j .. 2j + 2: their triangles
  for (std::size_t j = 0; j < K; ++j) {
    const double u = 2.0 * M_PI * (2.0 * static_cast<double>(j) + 1.0) / segments;
    const Eigen::Vector3d c(std::cos(u), std::sin(u), 0.0);
    double r = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int v = 0; v < 16; ++v)
        r = std::max(r, (mesh.vertices[static_cast<std::size_t>((2 * j + i) % segments) * 16 +
                                       static_cast<std::size_t>(v)] -
                         c)
                            .norm());
    ring.push_back({c, r * (1 + 1e-9)});
  }
  REQUIRE(certify_cover(mesh, ring).certified);
  CoverLowerBoundOptions o = settled();
  const CoverLowerBound chosen = cover_protrusion_lower_bound(query, K, o);
  o.count_even_witnesses = 8192;
  const CoverLowerBound even = cover_protrusion_lower_bound(query, K, o);
  const double ring_p = max_protrusion(query, ring);
  INFO("chosen weights " << chosen.count_bound << " with even witnesses " << even.count_bound
                         << " ring " << ring_p);
  CHECK(even.count_bound > 1.2 * chosen.count_bound);
  CHECK(even.bound <= ring_p);
  CHECK(even.pair_bound == chosen.pair_bound);
  // One thread gives the same bits: compared in the other builds. The sanitizer builds leave
  // out this third run, whose steps the two above have run.
  if (test::kSanitizerBuild) return;
  o.threads = 1;
  const CoverLowerBound one = cover_protrusion_lower_bound(query, K, o);
  CHECK(one.count_bound == even.count_bound);
  CHECK(one.count_points == even.count_points);
}

TEST_CASE("cover lower bound: the same for every thread count", "[cover_lower_bound]") {
  const MeshQuery query(make_torus(1.0, 0.3, 32, 12));
  CoverLowerBoundOptions one = quick(), two = quick();
  one.threads = 1;
  two.threads = 2;
  const CoverLowerBound a = cover_protrusion_lower_bound(query, 6, one);
  const CoverLowerBound b = cover_protrusion_lower_bound(query, 6, two);
  CHECK(a.bound == b.bound);
  CHECK(a.witnesses == b.witnesses);
  CHECK(a.count_bound == b.count_bound);
  CHECK(a.count_weights == b.count_weights);
}

TEST_CASE("cover lower bound rejects bad input", "[cover_lower_bound]") {
  const MeshQuery query(make_icosphere(1.0, 1));
  CHECK_THROWS_AS(cover_protrusion_lower_bound(query, 0), std::invalid_argument);
  const auto rejects = [&](CoverLowerBoundOptions o, const std::string& name) {
    try {
      cover_protrusion_lower_bound(query, 2, o);
      FAIL("accepted bad " << name);
    } catch (const std::invalid_argument& e) {
      CHECK(std::string(e.what()).find(name) != std::string::npos);
    }
  };
  CoverLowerBoundOptions o;
  o.resolution = 3;
  rejects(o, "resolution");
  o = {};
  o.candidates = 1;
  rejects(o, "candidates");
  o = {};
  o.starts = 0;
  rejects(o, "starts");
  o = {};
  o.count_witnesses = 1;
  rejects(o, "count_witnesses");
  o = {};
  o.count_passes = 0;
  rejects(o, "count_passes");
  o = {};
  o.count_even_witnesses = 1;
  rejects(o, "count_even_witnesses");
  o = {};
  o.threads = -1;
  rejects(o, "threads");
  try {
    cover_protrusion_lower_bound(query, 0);
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("budget") != std::string::npos);
  }
}
