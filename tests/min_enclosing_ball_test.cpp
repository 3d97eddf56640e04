// min_enclosing_ball against CGAL's exact Min_sphere_of_spheres_d on seeded random sets of
// points and balls, the closed forms of one and two balls, and bad input.

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include <CGAL/Cartesian.h>
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_3.h>
#include <catch2/catch.hpp>

#include "medspheres/min_enclosing_ball.h"

namespace {

using namespace medspheres;
constexpr double kEps = std::numeric_limits<double>::epsilon();

double cgal_radius(const std::vector<Sphere>& balls) {
  using Traits =
      CGAL::Min_sphere_of_spheres_d_traits_3<CGAL::Cartesian<double>, double, CGAL::Tag_true>;
  std::vector<Traits::Sphere> input;
  for (const Sphere& s : balls)
    input.emplace_back(Traits::Point(s.center.x(), s.center.y(), s.center.z()), s.radius);
  CGAL::Min_sphere_of_spheres_d<Traits> exact(input.begin(), input.end());
  REQUIRE(exact.is_valid());
  return exact.radius();
}

void check_against_cgal(const std::vector<Sphere>& balls) {
  const Sphere ball = min_enclosing_ball(balls);
  for (const Sphere& s : balls) CHECK((s.center - ball.center).norm() + s.radius <= ball.radius);
  const double exact = cgal_radius(balls);
  const double rounding = 64 * kEps * (ball.center.norm() + ball.radius);
  CHECK(ball.radius >= exact - rounding);
  CHECK(ball.radius <= exact * (1 + kEnclosingBallSlack) + rounding);
}

}  // namespace

TEST_CASE("min_enclosing_ball: random points and balls match CGAL's exact ball",
          "[min_enclosing_ball]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), radius(0.0, 0.5);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 1 + trial % 40;
    const bool points = trial % 2 == 0;
    const Eigen::Vector3d scale(1.0, trial % 3 == 0 ? 1e-3 : 1.0, 1.0);  // flat sets too
    std::vector<Sphere> balls;
    for (int i = 0; i < n; ++i)
      balls.push_back({Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(scale) * 10.0,
                       points ? 0.0 : radius(rng)});
    check_against_cgal(balls);
  }
}

TEST_CASE("min_enclosing_ball: one ball and two balls in closed form", "[min_enclosing_ball]") {
  const Sphere one{Eigen::Vector3d(1, 2, 3), 0.5};
  const Sphere same = min_enclosing_ball({one});
  CHECK(same.center == one.center);
  CHECK(same.radius == one.radius);
  // Two balls, neither inside the other: the segment of the farthest points is a diameter.
  const Sphere a{Eigen::Vector3d(0, 0, 0), 1.0}, b{Eigen::Vector3d(4, 0, 0), 0.5};
  const Sphere ab = min_enclosing_ball({a, b});
  CHECK(ab.radius == Approx((4.0 + 1.0 + 0.5) / 2.0).epsilon(1e-8));
  CHECK(ab.center.x() == Approx(-1.0 + 2.75).epsilon(1e-8));
  // A ball inside another: the larger one.
  const Sphere big{Eigen::Vector3d(0, 0, 0), 2.0}, small{Eigen::Vector3d(0.5, 0, 0), 0.3};
  const Sphere nested = min_enclosing_ball({small, big});
  CHECK(nested.radius == Approx(2.0).epsilon(1e-8));
  CHECK(nested.radius >= 2.0);
}

TEST_CASE("min_enclosing_ball: bad input is rejected", "[min_enclosing_ball]") {
  CHECK_THROWS_AS(min_enclosing_ball({}), std::invalid_argument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(min_enclosing_ball({{Eigen::Vector3d(nan, 0, 0), 1.0}}), std::invalid_argument);
  CHECK_THROWS_AS(min_enclosing_ball({{Eigen::Vector3d(0, 0, 0), -1.0}}), std::invalid_argument);
  CHECK_THROWS_AS(
      min_enclosing_ball({{Eigen::Vector3d(0, 0, 0), 1.0}, {Eigen::Vector3d(1, 0, 0), HUGE_VAL}}),
      std::invalid_argument);
}
