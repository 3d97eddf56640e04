#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/cover_certificate_json.h"
#include "medspheres/mesh/mesh_generators.h"

using namespace medspheres;

namespace {

TriangleMesh one_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c) {
  TriangleMesh m;
  m.vertices = {a, b, c};
  m.triangles = {{0, 1, 2}};
  return m;
}

// Distance from p to the union by brute force, the oracle.
double outside_union(const std::vector<Sphere>& balls, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Sphere& b : balls) best = std::min(best, (p - b.center).norm() - b.radius);
  return std::max(best, 0.0);
}

// The largest distance to the union over a barycentric grid of n^2 / 2 points of triangle t.
double dense_worst(const TriangleMesh& m, std::size_t t, const std::vector<Sphere>& balls, int n) {
  double worst = 0.0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double u = double(i) / n, v = double(j) / n;
      const Eigen::Vector3d p =
          (1 - u - v) * m.corner(t, 0) + u * m.corner(t, 1) + v * m.corner(t, 2);
      worst = std::max(worst, outside_union(balls, p));
    }
  return worst;
}

}  // namespace

TEST_CASE("a ball holding the three corners certifies the triangle unsplit", "[cover]") {
  const TriangleMesh m = one_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const CoverCertificate c = certify_cover(m, {{Eigen::Vector3d(0.3, 0.3, 0.1), 0.8}});
  CHECK(c.certified);
  CHECK(c.uncertified_triangles == 0);
  CHECK(c.pieces_tested == 1);
  CHECK(c.max_depth_reached == 0);
  CHECK(c.worst_triangle == -1);
}

TEST_CASE("two balls that hold a triangle only together certify it after splits", "[cover]") {
  const TriangleMesh m = one_triangle({-1, 0, 0}, {1, 0, 0}, {0, 0.2, 0});
  // Neither ball holds all three corners; their union holds the whole triangle (its
  // points are within 1.02 of one of the two centres).
  const std::vector<Sphere> balls = {{Eigen::Vector3d(-0.5, 0, 0), 0.75},
                                     {Eigen::Vector3d(0.5, 0, 0), 0.75}};
  REQUIRE(dense_worst(m, 0, balls, 400) == 0.0);
  const CoverCertificate c = certify_cover(m, balls);
  CHECK(c.certified);
  CHECK(c.max_depth_reached >= 1);
  CHECK(c.pieces_tested > 1);
}

TEST_CASE("a triangle poking out fails, and the worst point found is the true worst", "[cover]") {
  // Balls of radius 0.5 at x = -1 and x = 1 hold the corners; between them the triangle
  // is outside. Its farthest point from both centres is on x = 0 at the largest y, 5e-4:
  // distance sqrt(1 + 2.5e-7) - 0.5.
  const TriangleMesh m = one_triangle({-1, 0, 0}, {1, 0, 0}, {1, 1e-3, 0});
  const std::vector<Sphere> balls = {{Eigen::Vector3d(-1, 0, 0), 0.5},
                                     {Eigen::Vector3d(1, 0, 0), 0.5}};
  const double truth = std::sqrt(1.0 + 2.5e-7) - 0.5;
  CoverCertificateOptions o;
  o.worst_tolerance = 1e-6;
  const CoverCertificate c = certify_cover(m, balls, o);
  CHECK_FALSE(c.certified);
  CHECK(c.uncertified_triangles == 1);
  CHECK(c.proven_uncovered_triangles == 1);
  CHECK(c.worst_triangle == 0);
  CHECK(c.worst_distance <= truth + 1e-12);
  CHECK(c.worst_distance >= truth - 1e-6 - 1e-12);
  CHECK(c.worst_bound >= truth - 1e-12);
  CHECK(std::abs(c.worst_point.x()) < 2e-3);
  CHECK(outside_union(balls, c.worst_point) == Approx(c.worst_distance).margin(1e-12));
}

TEST_CASE("the certificate's JSON: every count, and the worst point when not certified",
          "[cover]") {
  const TriangleMesh m = one_triangle({-1, 0, 0}, {1, 0, 0}, {1, 1e-3, 0});
  const std::vector<Sphere> two = {{Eigen::Vector3d(-1, 0, 0), 0.5},
                                   {Eigen::Vector3d(1, 0, 0), 0.5}};
  for (const std::vector<Sphere>& balls :
       {two, std::vector<Sphere>{{Eigen::Vector3d(0, 0, 0), 2}}}) {
    const CoverCertificate c = certify_cover(m, balls);
    INFO(c.certified);
    const nlohmann::json j = nlohmann::json::parse(cover_certificate_json(c));
    CHECK(j["certified"] == c.certified);
    CHECK(j["triangles"] == c.triangles);
    CHECK(j["uncertified_triangles"] == c.uncertified_triangles);
    CHECK(j["proven_uncovered_triangles"] == c.proven_uncovered_triangles);
    CHECK(j["pieces_tested"] == c.pieces_tested);
    CHECK(j["max_depth"] == c.max_depth_reached);
    CHECK(j.contains("worst_uncovered_distance") == !c.certified);
    if (c.certified) continue;
    // doubles exactly, as nlohmann writes and reads them
    CHECK(j["worst_uncovered_distance"].get<double>() == c.worst_distance);
    CHECK(j["worst_uncovered_bound"].get<double>() == c.worst_bound);
    for (int k = 0; k < 3; ++k)
      CHECK(j["worst_uncovered_point"][k].get<double>() == c.worst_point[k]);
  }
}

TEST_CASE("random configurations: certified means no dense sample lies outside", "[cover]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), centre(-0.5, 0.5), r(0.4, 1.0);
  int certified = 0, failed = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const TriangleMesh m =
        one_triangle({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)});
    std::vector<Sphere> balls;
    for (int i = 0; i < 6; ++i)
      balls.push_back({Eigen::Vector3d(centre(rng), centre(rng), centre(rng)), r(rng)});
    CoverCertificateOptions o;
    o.worst_tolerance = 1e-5;
    const CoverCertificate c = certify_cover(m, balls, o);
    const double dense = dense_worst(m, 0, balls, 120);
    if (c.certified) {
      ++certified;
      CHECK(dense == 0.0);
    } else {
      ++failed;
      // The search's value is an attained distance, and within tolerance of the maximum.
      CHECK(c.worst_distance <= c.worst_bound);
      CHECK(dense <= c.worst_bound + 1e-12);
      if (c.worst_bound <= c.worst_distance + o.worst_tolerance)
        CHECK(c.worst_distance >= dense - 1e-5 - 1e-12);
    }
  }
  // Both outcomes occur, so the checks above are not vacuous.
  CHECK(certified > 20);
  CHECK(failed > 20);
}

TEST_CASE("rounding edge: a corner exactly on the sphere is not certified", "[cover]") {
  const Sphere unit{Eigen::Vector3d::Zero(), 1.0};
  // Corners on the unit sphere: the triangle lies in the closed ball, but the certificate
  // allows for rounding and so does not claim it.
  const TriangleMesh on = one_triangle({1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  const CoverCertificate c = certify_cover(on, {unit});
  CHECK_FALSE(c.certified);
  CHECK(c.proven_uncovered_triangles == 0);
  CHECK(c.worst_distance <= 1e-15);
  // One ulp outside: never certified.
  const double out = std::nextafter(1.0, 2.0);
  CHECK_FALSE(certify_cover(one_triangle({out, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}), {unit}).certified);
  CHECK_FALSE(ball_contains_certainly(unit, Eigen::Vector3d(1, 0, 0), 0.0));
  CHECK_FALSE(ball_contains_certainly(unit, Eigen::Vector3d(out, 0, 0), 0.0));
  // Inside by far more than the rounding: certified.
  const double in = 1.0 - 1e-12;
  CHECK(certify_cover(one_triangle({in, 0, 0}, {0, in, 0}, {0, 0, in}), {unit}).certified);
  // The position error counts: a point inside by 1e-12 with an error of 1e-11 is not held.
  CHECK(ball_contains_certainly(unit, Eigen::Vector3d(in, 0, 0), 0.0));
  CHECK_FALSE(ball_contains_certainly(unit, Eigen::Vector3d(in, 0, 0), 1e-11));
}

TEST_CASE("far from the origin the test still separates 1e-9 relative margins", "[cover]") {
  const Eigen::Vector3d o(1e6, -2e6, 3e6);
  const TriangleMesh m = one_triangle(o + Eigen::Vector3d(1, 0, 0), o + Eigen::Vector3d(0, 1, 0),
                                      o + Eigen::Vector3d(0, 0, 1));
  CHECK(certify_cover(m, {{o, 1.0 + 1e-6}}).certified);
  CHECK_FALSE(certify_cover(m, {{o, 1.0 - 1e-6}}).certified);
}

TEST_CASE("icosphere: the circumscribed ball certifies it, a smaller one misses by the gap",
          "[cover]") {
  const TriangleMesh m = make_icosphere(1.0, 3);
  CHECK(certify_cover(m, {{Eigen::Vector3d::Zero(), 1.0 + 1e-9}}).certified);
  const CoverCertificate c = certify_cover(m, {{Eigen::Vector3d::Zero(), 0.99}});
  CHECK_FALSE(c.certified);
  // The vertices are the farthest points, at distance 1: outside by 0.01.
  CHECK(c.worst_distance == Approx(0.01).margin(1e-9));
  CHECK(c.uncertified_triangles == m.num_triangles());
}

TEST_CASE("certify_cover: same answer for every thread count", "[cover]") {
  const TriangleMesh m = make_torus(1.0, 0.3, 24, 12);
  std::vector<Sphere> balls;
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * M_PI * i / 12;
    balls.push_back({Eigen::Vector3d(std::cos(a), std::sin(a), 0), 0.55});
  }
  CoverCertificateOptions o1, o2;
  o1.threads = 1;
  o2.threads = 2;
  const CoverCertificate a = certify_cover(m, balls, o1), b = certify_cover(m, balls, o2);
  CHECK(a.certified == b.certified);
  CHECK(a.triangle_certified == b.triangle_certified);
  CHECK(a.pieces_tested == b.pieces_tested);
  CHECK(a.worst_distance == b.worst_distance);
}

TEST_CASE("certify_cover over many blocks of triangles: each triangle as if alone", "[cover]") {
  // 81920 triangles: more than one block of the certification. Balls on the equator hold
  // a band of the sphere; each triangle's verdict and piece count must be those of the
  // triangle certified alone, and the reported pieces those of the first triangles.
  const TriangleMesh m = make_icosphere(1.0, 6);
  REQUIRE(m.num_triangles() > 65536);
  std::vector<Sphere> balls;
  for (int i = 0; i < 16; ++i) {
    const double a = 2 * M_PI * i / 16;
    balls.push_back({Eigen::Vector3d(std::cos(a), std::sin(a), 0), 0.45});
  }
  CoverCertificateOptions o;
  o.max_depth = 4;
  o.max_pieces_reported = 40;
  o.max_worst_evaluations = 2000;
  const CoverCertificate c = certify_cover(m, balls, o);
  REQUIRE(c.uncertified_triangles > 0);
  REQUIRE(c.uncertified_triangles < m.num_triangles());
  std::size_t first_uncertified = m.num_triangles();
  for (std::size_t t = 0; t < m.num_triangles(); ++t) {
    if (!c.triangle_certified[t]) {
      first_uncertified = std::min(first_uncertified, t);
    }
    if (t % 257 != 0 && (t < 65530 || t > 65540)) continue;
    const CoverCertificate alone =
        certify_cover(one_triangle(m.corner(t, 0), m.corner(t, 1), m.corner(t, 2)), balls, o);
    CHECK(alone.certified == (c.triangle_certified[t] != 0));
  }
  REQUIRE(c.uncertified_pieces.size() == 40);
  CHECK(c.uncertified_pieces.front().triangle == static_cast<int>(first_uncertified));
  for (std::size_t i = 1; i < c.uncertified_pieces.size(); ++i)
    CHECK(c.uncertified_pieces[i - 1].triangle <= c.uncertified_pieces[i].triangle);
}

TEST_CASE("certify_cover rejects bad input", "[cover]") {
  const TriangleMesh m = one_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  CHECK_THROWS_AS(certify_cover(m, {{Eigen::Vector3d::Zero(), -1.0}}), InputError);
  CoverCertificateOptions o;
  o.max_depth = 31;
  CHECK_THROWS_AS(certify_cover(m, {{Eigen::Vector3d::Zero(), 1.0}}, o), std::invalid_argument);
  CHECK_FALSE(certify_cover(m, {}).certified);
}
