#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/forward_kinematics.h"
#include "support/robot_fixtures.h"

using Catch::Matchers::Contains;
using medspheres::KinematicTree;
using medspheres::test::three_link_arm;

namespace {

// Poses are compared entry by entry: hand-computed values carry a few ulps of rounding
// (sin and cos of pi/2 are not exactly 1 and 0 in floating point).
void check_pose(const Eigen::Isometry3d& X, const Eigen::Matrix3d& R, const Eigen::Vector3d& p) {
  CHECK((X.linear() - R).cwiseAbs().maxCoeff() < 1e-14);
  CHECK((X.translation() - p).cwiseAbs().maxCoeff() < 1e-14);
}

Eigen::Matrix3d rot(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

}  // namespace

TEST_CASE("forward kinematics matches hand-computed poses of a three-link arm", "[fk]") {
  const KinematicTree tree(three_link_arm());
  REQUIRE(tree.joint_names() == std::vector<std::string>{"j1", "j2"});
  const double theta = M_PI / 2, d = 0.3;
  const auto X = tree.link_poses(Eigen::Vector2d(theta, d));
  REQUIRE(X.size() == 5);
  check_pose(X[0], Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  // l1: T(0,0,1) Rz(theta).
  check_pose(X[1], rot(theta, Eigen::Vector3d::UnitZ()), {0, 0, 1});
  // l2: X_l1 T(1,0,0) Rx(pi/2) T(d,0,0): position (0,0,1) + Rz(90)(1,0,0) + Rz(90)Rx(90)(d,0,0)
  // = (0, 1 + d, 1); its axes x -> (0,1,0), y -> (0,0,1), z -> (1,0,0).
  Eigen::Matrix3d R2;
  R2 << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  check_pose(X[2], R2, {0, 1 + d, 1});
  // l3: the mimic angle is 2 theta + 0.1 about y, after T(0,0,0.5): l2's z is world x.
  const double phi = 2 * theta + 0.1;
  check_pose(X[3], R2 * rot(phi, Eigen::Vector3d::UnitY()), {0.5, 1 + d, 1});
  // tool: 0.2 along l3's z = R2 (sin phi, 0, cos phi) = (cos phi, sin phi, 0).
  check_pose(X[4], R2 * rot(phi, Eigen::Vector3d::UnitY()),
             {0.5 + 0.2 * std::cos(phi), 1 + d + 0.2 * std::sin(phi), 1});
}

TEST_CASE("a base pose moves every link, the by-name overload agrees", "[fk]") {
  const KinematicTree tree(three_link_arm());
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.linear() = rot(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  X_WB.translation() = Eigen::Vector3d(-1, 4, 2);
  const Eigen::Vector2d q(-0.4, 0.25);
  const auto local = tree.link_poses(q);
  const auto world = tree.link_poses(q, X_WB);
  const auto named =
      tree.link_poses(std::map<std::string, double>{{"j2", 0.25}, {"j1", -0.4}}, X_WB);
  for (std::size_t i = 0; i < local.size(); ++i) {
    CHECK(((X_WB * local[i]).matrix() - world[i].matrix()).cwiseAbs().maxCoeff() < 1e-14);
    CHECK(named[i].matrix() == world[i].matrix());
  }
  // Absent joints are at 0.
  const auto zero = tree.link_poses(std::map<std::string, double>{});
  const auto zero_v = tree.link_poses(Eigen::Vector2d::Zero());
  CHECK(zero[4].matrix() == zero_v[4].matrix());
  CHECK(tree.link_index("l3") == 3);
  CHECK_THROWS_AS(tree.link_index("nope"), std::invalid_argument);
}

TEST_CASE("forward kinematics rejects bad positions, naming the joint", "[fk]") {
  const KinematicTree tree(three_link_arm());
  auto message = [&](auto&& call) -> std::string {
    try {
      call();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  CHECK_THAT(message([&] { tree.link_poses(Eigen::Vector3d(0, 0, 0)); }), Contains("3 joint"));
  CHECK_THAT(message([&] {
               tree.link_poses(Eigen::Vector2d(0, std::numeric_limits<double>::quiet_NaN()));
             }),
             Contains("\"j2\""));
  using Named = std::map<std::string, double>;
  CHECK_THAT(message([&] { tree.link_poses(Named{{"j9", 0}}); }), Contains("\"j9\""));
  CHECK_THAT(message([&] { tree.link_poses(Named{{"j3", 0}}); }), Contains("mimic"));
  CHECK_THAT(message([&] { tree.link_poses(Named{{"tool_joint", 0}}); }), Contains("fixed"));
}

TEST_CASE("one tree answers many threads at once with the serial result", "[fk]") {
  const KinematicTree tree(three_link_arm());
  std::vector<std::thread> threads;
  std::vector<int> mismatches(4, 0);
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 200; ++i) {
        const Eigen::Vector2d q(0.01 * i - t, 0.001 * i);
        const auto a = tree.link_poses(q);
        const auto b = medspheres::forward_kinematics(three_link_arm(), q);
        for (std::size_t k = 0; k < a.size(); ++k)
          if (a[k].matrix() != b[k].matrix()) ++mismatches[t];
      }
    });
  }
  for (auto& th : threads) th.join();
  for (int m : mismatches) CHECK(m == 0);
}
