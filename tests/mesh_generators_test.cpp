#include <cmath>

#include <catch2/catch.hpp>

#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_report.h"

using namespace medspheres;

namespace {
constexpr double kPi = 3.14159265358979323846;

void check_closed_outward(const TriangleMesh& m, long euler) {
  const MeshReport r = analyze_mesh(m);
  CHECK(r.closed);
  CHECK(r.components == 1);
  CHECK(r.degenerate_triangles == 0);
  CHECK(r.inconsistent_edges == 0);
  CHECK(r.is_closed_outward());
  CHECK(static_cast<long>(r.vertices) - static_cast<long>(r.edges) +
            static_cast<long>(r.triangles) ==
        euler);
}
}  // namespace

TEST_CASE("generated box is closed, outward, and exact", "[generators]") {
  for (int n : {1, 2, 5}) {
    const TriangleMesh m = make_box({1.0, 2.0, 0.5}, n);
    check_closed_outward(m, 2);
    CHECK(m.triangles.size() == 12u * n * n);
    CHECK(analyze_mesh(m).signed_volume == Approx(8.0 * 1.0 * 2.0 * 0.5).epsilon(1e-12));
  }
}

TEST_CASE("generated icosphere converges to the ball volume from below", "[generators]") {
  double prev = 0.0;
  for (int s = 0; s <= 4; ++s) {
    const TriangleMesh m = make_icosphere(2.0, s);
    check_closed_outward(m, 2);
    const double v = analyze_mesh(m).signed_volume;
    CHECK(v < 4.0 / 3.0 * kPi * 8.0);
    CHECK(v > prev);
    prev = v;
    for (const auto& p : m.vertices) CHECK(p.norm() == Approx(2.0).epsilon(1e-14));
  }
  CHECK(prev == Approx(4.0 / 3.0 * kPi * 8.0).epsilon(0.01));
}

TEST_CASE("generated torus and capsule are closed and near their volumes", "[generators]") {
  const TriangleMesh t = make_torus(1.0, 0.25, 128, 64);
  check_closed_outward(t, 0);
  CHECK(analyze_mesh(t).signed_volume == Approx(2 * kPi * kPi * 1.0 * 0.0625).epsilon(0.01));

  const TriangleMesh c = make_capsule(0.5, 1.0, 64, 16);
  check_closed_outward(c, 2);
  const double vc = kPi * 0.25 * (4.0 / 3.0 * 0.5 + 2.0);
  CHECK(analyze_mesh(c).signed_volume == Approx(vc).epsilon(0.01));

  const TriangleMesh ball = make_capsule(0.5, 0.0, 32, 8);  // degenerates to a sphere
  check_closed_outward(ball, 2);
}

TEST_CASE("generators reject nonsense parameters", "[generators]") {
  CHECK_THROWS_AS(make_box({1, 0, 1}), std::invalid_argument);
  CHECK_THROWS_AS(make_box({1, 1, 1}, 0), std::invalid_argument);
  CHECK_THROWS_AS(make_icosphere(-1, 2), std::invalid_argument);
  CHECK_THROWS_AS(make_torus(0.5, 1.0, 8, 8), std::invalid_argument);
  CHECK_THROWS_AS(make_torus(1.0, 0.5, 2, 8), std::invalid_argument);
  CHECK_THROWS_AS(make_capsule(1.0, -1.0, 8, 2), std::invalid_argument);
}

TEST_CASE("generated cylinder is the closed prism inscribed in the cylinder", "[generators]") {
  for (int slices : {3, 7, 32}) {
    const TriangleMesh m = make_cylinder(0.5, 1.5, slices);
    check_closed_outward(m, 2);
    CHECK(m.triangles.size() == 4u * static_cast<unsigned>(slices));
    // The regular slices-gon of circumradius r has area (slices / 2) r^2 sin(2 pi / slices).
    const double area = 0.5 * slices * 0.25 * std::sin(2 * kPi / slices);
    CHECK(analyze_mesh(m).signed_volume == Approx(area * 3.0).epsilon(1e-12));
    for (const auto& p : m.vertices) {
      CHECK(std::abs(std::abs(p.z()) - 1.5) < 1e-15);
      const double rho = std::hypot(p.x(), p.y());
      CHECK((rho == 0.0 || std::abs(rho - 0.5) < 1e-15));
    }
  }
  CHECK_THROWS_AS(make_cylinder(0.5, 0.0, 8), std::invalid_argument);
  CHECK_THROWS_AS(make_cylinder(0.5, 1.0, 2), std::invalid_argument);
}
