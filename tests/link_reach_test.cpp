// link_reach (src/check/link_reach.h): every sphere of every link, posed by KinematicTree at
// angles far beyond the joints' limits, lies in its link's ball; and a checker that skips the
// scene tests of the links whose ball stays clear of the scene gives brute force's verdicts.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "../src/check/link_reach.h"
#include "../src/check/robot_layout.h"
#include "medspheres/check/robot_checker.h"
#include "medspheres/forward_kinematics.h"
#include "support/check_fixtures.h"

using namespace medspheres;
using check::detail::LinkReach;
using test::pose_of;

namespace {

// Configurations of the capsule arm: angles in [-20, 20] (beyond its limits of 2.8), the
// finger's slide in [0, 0.04].
std::vector<Eigen::VectorXd> wild_configs(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-20.0, 20.0), slide(0.0, 0.04);
  std::vector<Eigen::VectorXd> out;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::VectorXd q(8);
    for (int j = 0; j < 7; ++j) q[j] = angle(rng);
    q[7] = slide(rng);
    out.push_back(q);
  }
  return out;
}

// A box of half sides h at c: the distance from p (0 inside).
double box_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& c, const Eigen::Vector3d& h) {
  const Eigen::Vector3d d = (p - c).cwiseAbs() - h;
  return d.cwiseMax(0.0).norm();
}

}  // namespace

TEST_CASE("link reach: every sphere of a link inside its ball at any angle", "[check]") {
  const RobotModel arm = test::capsule_arm(5);
  const Eigen::Isometry3d X_WB = pose_of({0.3, -0.2, 0.1}, 0.2, -0.4, 1.1);
  const check::detail::RobotLayout layout = check::detail::make_layout(arm, nullptr, X_WB, {}, {});
  const std::vector<LinkReach> reach = check::detail::link_reach(layout);
  REQUIRE(reach.size() == layout.link_names.size());
  const KinematicTree tree(arm);
  std::vector<double> fill(reach.size(), 0.0);  // per link: the largest |c - centre| + r, / radius
  for (const Eigen::VectorXd& q : wild_configs(3000, 5)) {
    const std::vector<Eigen::Isometry3d> X = tree.link_poses(q, X_WB);
    for (std::size_t l = 0; l < reach.size(); ++l) {
      if (std::isinf(reach[l].radius)) continue;
      const std::string& name = layout.link_names[l];
      const Link& link = *arm.find_link(name);
      const Eigen::Isometry3d& X_WL = X[tree.link_index(name)];
      for (const SphereSet* set : {&link.spheres.outer, &link.spheres.inner})
        for (const Sphere& s : set->spheres) {
          const double far = (X_WL * s.center - reach[l].centre).norm() + s.radius;
          REQUIRE(far <= reach[l].radius * (1 + 1e-12));
          fill[l] = std::max(fill[l], far / reach[l].radius);
        }
    }
  }
  for (std::size_t l = 0; l < reach.size(); ++l) {
    const std::string& name = layout.link_names[l];
    INFO(name << ": radius " << reach[l].radius << ", filled to " << fill[l]);
    // Below the prismatic slides, no ball; every other link's ball is finite.
    CHECK(std::isinf(reach[l].radius) == (name == "finger_a" || name == "finger_b"));
    // The ball is no vague bound: the spheres come near its edge (the base, fixed, and the
    // first moving link reach it; the chain's sums leave the others some room).
    if (name == "l0" || name == "l1") CHECK(fill[l] > 0.999);
    if (!std::isinf(reach[l].radius)) CHECK(fill[l] > 0.6);
  }
}

TEST_CASE("links far from the scene: their scene tests skipped, brute force's verdicts",
          "[check]") {
  const RobotModel arm = test::capsule_arm(5);
  // A box above the arm that only the outer links reach.
  const Eigen::Vector3d centre(0.0, 0.0, 0.55), half(0.5, 0.5, 0.05);
  check::Scene scene;
  scene.add_box(2 * half, pose_of(centre), "ceiling");
  const double margin = 0.01;
  const check::detail::RobotLayout layout =
      check::detail::make_layout(arm, nullptr, Eigen::Isometry3d::Identity(), {}, {});
  const check::detail::SceneGrid grid(scene, 0.05, 0.0, 1 << 16, 1e-9);
  const std::vector<unsigned char> far = check::detail::links_far_from_scene(layout, grid, margin);
  // Every link the function calls far stays clear at every configuration sampled.
  const KinematicTree tree(arm);
  const std::vector<Eigen::VectorXd> configs = wild_configs(2000, 9);
  for (const Eigen::VectorXd& q : configs) {
    const std::vector<Eigen::Isometry3d> X = tree.link_poses(q);
    for (std::size_t l = 0; l < far.size(); ++l) {
      if (!far[l]) continue;
      const std::string& name = layout.link_names[l];
      for (const Sphere& s : arm.find_link(name)->spheres.outer.spheres)
        REQUIRE(box_distance(X[tree.link_index(name)] * s.center, centre, half) - s.radius >
                margin);
    }
  }
  for (const check::Simd simd : {check::Simd::scalar, check::Simd::automatic})
    for (const bool floats : {true, false}) {
      check::CheckerOptions o;
      o.margin = margin;
      o.self = false;
      o.simd = simd;
      o.float_tests = floats;
      const check::RobotChecker checker(arm, scene, o);
      const std::size_t skipped = checker.grid().far_links;
      INFO("skipped " << skipped);
      CHECK(skipped >= 3);                           // the base and the links near it
      CHECK(skipped + 5 <= checker.links().size());  // the fingers and the outer links
      std::vector<double> q;
      for (const Eigen::VectorXd& c : configs) q.insert(q.end(), c.data(), c.data() + 8);
      std::vector<check::Verdict> v(configs.size());
      checker.check(q.data(), v.size(), check::Mode::spheres, v.data(), 1);
      std::size_t colliding = 0, disagree = 0;
      for (std::size_t k = 0; k < configs.size(); ++k) {
        const std::vector<Eigen::Isometry3d> X = tree.link_poses(configs[k]);
        bool truth = false;
        for (std::size_t i = 0; i < arm.links.size() && !truth; ++i) {
          const Eigen::Isometry3d& X_WL = X[tree.link_index(arm.links[i].name)];
          for (const Sphere& s : arm.links[i].spheres.outer.spheres)
            truth = truth || box_distance(X_WL * s.center, centre, half) - s.radius <= margin;
        }
        colliding += truth;
        disagree += truth != (v[k] == check::Verdict::colliding);
      }
      CHECK(disagree == 0);
      CHECK(colliding > configs.size() / 20);  // the comparison means something
    }
}
