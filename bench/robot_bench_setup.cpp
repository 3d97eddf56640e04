// bench_robot's and bench_checker's common setup (robot_bench_setup.h).

#include "robot_bench_setup.h"

#include <algorithm>
#include <cstdlib>
#include <system_error>

#include <unistd.h>

#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/formats/srdf_disabled_collisions.h"
#include "robot_bench_exact.h"
#include "support/coarse_arm.h"

namespace medspheres::bench {
namespace {

// Every joint at 0, clamped to its limits.
Eigen::VectorXd default_config(const RobotModel& model, const KinematicTree& tree) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tree.num_positions()));
  for (Eigen::Index k = 0; k < q.size(); ++k) {
    const Joint& j = *model.find_joint(tree.joint_names()[static_cast<std::size_t>(k)]);
    if (j.type != JointType::kContinuous && j.limits)
      q[k] = std::clamp(0.0, j.limits->lower, j.limits->upper);
  }
  return q;
}

}  // namespace

NamePairs disabled_pairs(const std::string& srdf, double margin, const BenchRobot& robot,
                         std::size_t& by_default) {
  NamePairs out;
  if (!srdf.empty())
    for (const auto& d : formats::load_srdf_disabled_collisions(srdf))
      out.emplace_back(d.link1, d.link2);
  const fcl::RobotBounds all(robot.model, robot.meshes, out);
  ExactRobot exact(all, robot.exact, {}, robot.solids);
  const Eigen::VectorXd q0 = default_config(robot.model, all.kinematics());
  const auto near = exact.self_pairs_within(all.poses(q0, Eigen::Isometry3d::Identity()), margin);
  for (const auto& [a, b] : near)
    out.emplace_back(all.geometries()[a].link(), all.geometries()[b].link());
  by_default = near.size();
  return out;
}

GeneratedRobot::GeneratedRobot(const std::string& name, const std::string& cache_dir) {
  if (name.empty()) return;
  namespace fs = std::filesystem;
  fs::path dir = fs::path(cache_dir) / "coarse_arm";
  if (cache_dir.empty())
    dir = temp_ =
        fs::temp_directory_path() / ("medspheres-bench-coarse-arm-" + std::to_string(::getpid()));
  urdf_ = test::write_coarse_arm(dir);
}

GeneratedRobot::~GeneratedRobot() {
  std::error_code ec;
  if (!temp_.empty()) std::filesystem::remove_all(temp_, ec);
}

void restart_with_passive_openmp(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  setenv("OMP_WAIT_POLICY", "passive", 1);
  execv("/proc/self/exe", argv);  // returns only on failure: go on as we are
}

}  // namespace medspheres::bench
