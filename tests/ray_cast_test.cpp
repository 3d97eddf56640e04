// MeshQuery::cast_ray against brute force over every triangle, computed another way:
// the ray meets the triangle's plane at t = n.(a - o) / n.d, and that point is inside
// when it lies on the inner side of all three edges. Rays passing within a small margin
// of an edge, grazing a plane, or crossing near t = 0 or the limit are ambiguous to
// rounding and skipped (the test checks that few are).
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_query.h"

using namespace medspheres;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Oracle {
  RayCrossings answer;
  bool ambiguous = false;
};

Oracle brute_force(const TriangleMesh& m, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                   double limit, bool count_all) {
  const double scale = m.bounds().sizes().norm() + (o - m.bounds().center()).norm();
  const double margin = 1e-9 * scale;
  Oracle out;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Eigen::Vector3d &a = m.corner(t, 0), &b = m.corner(t, 1), &c = m.corner(t, 2);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double nn = n.norm(), nd = n.dot(d);
    if (std::abs(nd) <= 1e-9 * nn * d.norm()) {
      // Grazing: ambiguous only if the ray passes near the triangle's plane at all.
      if (std::abs(n.dot(o - a)) <= margin * nn) out.ambiguous = true;
      continue;
    }
    const double th = n.dot(a - o) / nd;
    const Eigen::Vector3d p = o + th * d;
    double inside = kInf;  // signed distance to the nearest edge line, > 0 inside
    const Eigen::Vector3d v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = v[(k + 1) % 3] - v[k];
      inside = std::min(inside, n.dot(e.cross(p - v[k])) / (nn * e.norm()));
    }
    if (std::abs(inside) <= margin) {
      out.ambiguous = true;
      continue;
    }
    if (inside < 0.0) continue;
    if (std::abs(th) <= margin || std::abs(th - limit) <= margin) out.ambiguous = true;
    if (th < 0.0 || th >= limit) continue;
    if (count_all) out.answer.winding += nd < 0.0 ? 1 : -1;
    if (th < out.answer.t) out.answer.t = th, out.answer.triangle = static_cast<int>(t);
  }
  return out;
}

// Random triangles in the unit cube: overlapping, open, of every orientation.
TriangleMesh triangle_soup(int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  TriangleMesh m;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d c(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k)
      m.vertices.push_back(c + 0.2 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    m.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  return m;
}

}  // namespace

TEST_CASE("cast_ray agrees with brute force over every triangle", "[mesh_query][ray]") {
  std::mt19937_64 rng(20261125);
  const TriangleMesh meshes[] = {make_torus(1.0, 0.35, 40, 24), make_icosphere(0.8, 3),
                                 make_box(Eigen::Vector3d(0.5, 0.3, 0.7), 3),
                                 triangle_soup(400, rng)};
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g;
  for (const TriangleMesh& mesh : meshes) {
    const MeshQuery query(mesh);
    int kept = 0, hits = 0, total = 0, crossings = 0;
    for (int i = 0; i < 600; ++i) {
      // Origins inside and around the mesh's box (some at 3x its size); directions
      // towards a point of the box (odd rays), random, or along an axis (every fourth
      // ray: the slab test's flat case).
      const double spread = i % 3 == 0 ? 3.0 : 1.5;
      const Eigen::Vector3d o(spread * u(rng), spread * u(rng), spread * u(rng));
      Eigen::Vector3d d(g(rng), g(rng), g(rng));
      if (i % 2 == 1) {
        const Eigen::Vector3d f(u(rng), u(rng), u(rng));
        d = mesh.bounds().center() + 0.5 * mesh.bounds().sizes().cwiseProduct(f) - o;
      }
      if (i % 4 == 0) d = Eigen::Vector3d::Unit(i / 4 % 3) * (i % 8 == 0 ? 1.0 : -1.0);
      d *= i % 5 == 0 ? 7.0 : 1.0 / d.norm();  // t need not be a length
      const double limit = i % 2 == 0 ? kInf : 2.0 * std::abs(u(rng));
      const bool count_all = i % 3 != 1;
      ++total;
      const Oracle want = brute_force(mesh, o, d, limit, count_all);
      if (want.ambiguous) continue;
      ++kept;
      const RayCrossings got = query.cast_ray(o, d, limit, count_all);
      INFO("ray " << i << " from " << o.transpose() << " along " << d.transpose());
      REQUIRE(got.triangle == want.answer.triangle);
      REQUIRE(got.winding == want.answer.winding);
      if (want.answer.triangle >= 0) {
        ++hits;
        REQUIRE(got.t == Approx(want.answer.t).epsilon(1e-9));
      } else {
        REQUIRE(got.t == kInf);
      }
      crossings += std::abs(got.winding);
    }
    CHECK(kept >= total * 9 / 10);
    CHECK(hits >= kept / 6);
    CHECK(crossings > 0);
  }
}

TEST_CASE("cast_ray: closed meshes have winding 1 inside and 0 outside", "[mesh_query][ray]") {
  const MeshQuery query(make_icosphere(1.0, 2));
  const Eigen::Vector3d d = Eigen::Vector3d(0.3, -0.5, 0.81).normalized();
  // From outside, every crossing of a full ray: in and out again.
  CHECK(query.cast_ray(Eigen::Vector3d(-3.0, 5.0, -8.1), d, kInf, true).winding == 0);
  // From the centre: one crossing, out of the solid.
  const RayCrossings out = query.cast_ray(Eigen::Vector3d::Zero(), d, kInf, true);
  CHECK(out.winding == -1);
  CHECK(out.t == Approx(1.0).epsilon(0.05));
}

TEST_CASE("cast_ray rejects bad rays", "[mesh_query][ray]") {
  const MeshQuery query(make_icosphere(1.0, 1));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(query.cast_ray(Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d::UnitX()),
                  std::invalid_argument);
  CHECK_THROWS_AS(query.cast_ray(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
                  std::invalid_argument);
  CHECK_THROWS_AS(query.cast_ray(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, kInf, 0)),
                  std::invalid_argument);
  CHECK_THROWS_AS(query.cast_ray(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), nan),
                  std::invalid_argument);
}
