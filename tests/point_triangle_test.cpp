// The point-triangle kernel (medspheres/point_triangle.h) against the 113-bit oracle of
// support/point_triangle_oracle.h, a different construction, on the shapes where a plain
// kernel goes wrong: degenerate triangles (points, segments, collinear and nearly
// collinear corners), slivers, and query points far from small triangles.

#include <algorithm>
#include <cmath>
#include <random>

#include <catch2/catch.hpp>

#include "medspheres/point_triangle.h"
#include "support/point_triangle_oracle.h"

namespace {

using Eigen::Vector3d;
namespace test = medspheres::test;

// The header's promise: the point is within 32 u S of the triangle, its distance to p
// within 32 u S of the oracle's, S = |p| + |p - a| + L.
void check_kernel(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const double tolerance = 32.0 * 0x1p-53 * (p.norm() + (p - a).norm() + longest);
  const Vector3d q = medspheres::closest_point_on_triangle(p, a, b, c);
  const double want = test::oracle_distance(p, a, b, c);
  INFO("p " << p.transpose() << "  a " << a.transpose() << "  b " << b.transpose() << "  c "
            << c.transpose() << "  got " << (p - q).norm() << "  oracle " << want);
  CHECK(std::abs((p - q).norm() - want) <= tolerance);
  CHECK(test::oracle_distance(q, a, b, c) <= tolerance);
}

Vector3d random_vector(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vector3d(u(rng), u(rng), u(rng));
}

// Projection onto a convex set: q is the nearest point of triangle T to p iff q is in T
// and (p - q) . (x - q) <= 0 for every x in T, enough to check at the corners.
void check_projection(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c,
                      const Vector3d& q) {
  const double scale = 1 + p.norm() + a.norm() + b.norm() + c.norm();
  const double tol = 1e-12 * scale * scale;
  for (const Vector3d& x : {a, b, c}) CHECK((p - q).dot(x - q) <= tol);
  // q is a convex combination of the corners (least squares in the triangle's plane).
  const Vector3d n = (b - a).cross(c - a);
  if (n.norm() > 1e-9 * scale) {
    const double area = n.squaredNorm();
    CHECK((c - b).cross(q - b).dot(n) / area >= -1e-9);
    CHECK((a - c).cross(q - c).dot(n) / area >= -1e-9);
    CHECK((b - a).cross(q - a).dot(n) / area >= -1e-9);
    CHECK(std::abs(n.normalized().dot(q - a)) <= 1e-12 * scale);
  }
}

}  // namespace

TEST_CASE("point-triangle kernel: the closest point is the projection", "[point_triangle]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2, 2);
  auto rnd = [&] { return Vector3d(u(rng), u(rng), u(rng)); };
  for (int k = 0; k < 20000; ++k) {
    const Vector3d a = rnd(), b = rnd(), c = rnd(), p = rnd();
    check_projection(p, a, b, c, medspheres::closest_point_on_triangle(p, a, b, c));
  }
}

TEST_CASE("point-triangle kernel: degenerate triangles are their segment or point",
          "[point_triangle]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int i = 0; i < 3000; ++i) {
    const Vector3d a = random_vector(rng, 2.0), b = random_vector(rng, 2.0);
    const Vector3d p = random_vector(rng, 3.0), e = random_vector(rng, 1.0);
    check_kernel(p, a, a, a);                       // a point
    check_kernel(p, a, b, b);                       // a repeated corner
    check_kernel(p, a, a, b);                       // the same, other corners
    check_kernel(p, a, b, a + u01(rng) * (b - a));  // collinear, up to rounding
    check_kernel(p, a, b, a + 2.0 * (b - a));       // collinear, third corner outside
    // Nearly collinear, below and around the degenerate threshold 2 area = 2^-48 L^2.
    const double w = std::ldexp(1.0, -40 - (i % 24));
    check_kernel(p, a, b, a + u01(rng) * (b - a) + w * e);
  }
  // Closed forms: the point, and the segment from (0, 0, 0) to (2, 0, 0).
  const Vector3d o(0, 0, 0), x(2, 0, 0);
  CHECK(medspheres::closest_point_on_triangle(Vector3d(1, 1, 1), o, o, o) == o);
  CHECK(medspheres::closest_point_on_triangle(Vector3d(1.5, 3, -4), o, x, Vector3d(1, 0, 0)) ==
        Vector3d(1.5, 0, 0));
  CHECK(medspheres::closest_point_on_triangle(Vector3d(-1, 3, 0), x, o, x) == o);
}

TEST_CASE("point-triangle kernel: slivers and needles", "[point_triangle]") {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int i = 0; i < 3000; ++i) {
    const Vector3d a = random_vector(rng, 1.0), d = random_vector(rng, 1.0);
    const Vector3d e = random_vector(rng, 1.0);
    const double thin = std::pow(10.0, -2.0 - 14.0 * (i % 8) / 7.0);  // 1e-2 .. 1e-16
    const Vector3d c = a + u01(rng) * d + thin * e;
    // Near the sliver (where its regions are told apart) and anywhere.
    check_kernel(a + u01(rng) * d + thin * random_vector(rng, 4.0), a, a + d, c);
    check_kernel(random_vector(rng, 2.0), a, a + d, c);
  }
}

TEST_CASE("point-triangle kernel: query points far from small triangles", "[point_triangle]") {
  std::mt19937_64 rng(13);
  for (int i = 0; i < 3000; ++i) {
    const double size = std::pow(10.0, -6.0 + 12.0 * (i % 13) / 12.0);       // 1e-6 .. 1e6
    const double far = size * std::pow(10.0, 2.0 + 10.0 * (i % 11) / 10.0);  // 1e2 .. 1e12
    const Vector3d centre = random_vector(rng, 10.0 * size);
    const Vector3d a = centre + random_vector(rng, size), b = centre + random_vector(rng, size);
    const Vector3d c = centre + random_vector(rng, size);
    const Vector3d p = centre + far * random_vector(rng, 1.0).normalized();
    check_kernel(p, a, b, c);
    check_kernel(p, a, b, a + 0.5 * (b - a));  // far from a segment too
  }
}

TEST_CASE("point-triangle kernel: the one-off and the prepared query agree to the bit",
          "[point_triangle]") {
  // closest_point_on_triangle skips the accurate normal where it can; the answer must
  // still be the prepared one (MeshQuery's and TriangleTree's). Shapes around the thin
  // threshold (kappa = L^2 / 2A = 8: height 1/8 over a unit base) and the degenerate
  // one, and random ones.
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const Vector3d a = random_vector(rng, 1.0), d = random_vector(rng, 1.0).normalized();
    const Vector3d e = d.cross(random_vector(rng, 1.0)).normalized();
    const double height = i % 3 == 0   ? 0.125 * (1.0 + 1e-6 * (u01(rng) - 0.5))
                          : i % 3 == 1 ? std::ldexp(1.0, -47 - i % 6)
                                       : u01(rng);
    const Vector3d b = a + d, c = a + u01(rng) * d + height * e;
    const medspheres::detail::PreparedTriangle t = medspheres::detail::prepare_triangle(a, b, c);
    for (int k = 0; k < 4; ++k) {
      const Vector3d p = a + u01(rng) * d + 0.5 * height * random_vector(rng, 1.0) +
                         (k == 3 ? random_vector(rng, 2.0) : Vector3d::Zero());
      REQUIRE(medspheres::closest_point_on_triangle(p, a, b, c) ==
              medspheres::detail::closest_on_triangle(p, t.triangle, t.plane.normal));
    }
  }
}
