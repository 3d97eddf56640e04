#include <limits>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/sphere_set.h"

using medspheres::SphereSet;

TEST_CASE("SphereSet::bounds is the union of the balls' boxes", "[sphere_set]") {
  SphereSet s;
  CHECK(s.bounds().isEmpty());
  s.spheres.push_back({{1, 2, 3}, 0.5});
  s.spheres.push_back({{-1, 0, 0}, 2.0});
  const Eigen::AlignedBox3d b = s.bounds();
  CHECK(b.min() == Eigen::Vector3d(-3, -2, -2));
  CHECK(b.max() == Eigen::Vector3d(1.5, 2.5, 3.5));
}

TEST_CASE("validate_sphere_set rejects non-positive and non-finite values", "[sphere_set]") {
  SphereSet s;
  s.spheres.push_back({{0, 0, 0}, 1.0});
  CHECK_NOTHROW(medspheres::validate_sphere_set(s, "x"));
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double r : {0.0, -1.0, inf, nan}) {
    s.spheres[0].radius = r;
    CHECK_THROWS_AS(medspheres::validate_sphere_set(s, "x"), medspheres::InputError);
  }
  // Points (radius 0) only when allowed; the rest is refused as before.
  s.spheres[0].radius = 0.0;
  CHECK_NOTHROW(medspheres::validate_sphere_set(s, "x", true));
  for (double r : {-1.0, -0.0 - 1e-300, inf, nan}) {
    s.spheres[0].radius = r;
    CHECK_THROWS_AS(medspheres::validate_sphere_set(s, "x", true), medspheres::InputError);
  }
  s.spheres[0].radius = 1.0;
  s.spheres[0].center.y() = nan;
  CHECK_THROWS_WITH(medspheres::validate_sphere_set(s, "file.json"),
                    Catch::Matchers::StartsWith("file.json: sphere 0"));
}
