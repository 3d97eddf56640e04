// bench_robot's and bench_checker's common setup (robot_bench_setup.h).

#include "robot_bench_setup.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <system_error>

#include <unistd.h>

#include "medspheres/error.h"
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

RobotBenchOptions::RobotBenchOptions() {
  const std::string shared = std::string(MEDSPHERES_SOURCE_DIR) + "/../shared";
  robot.urdf = shared + "/robots/unitree_g1/g1_29dof_rev_1_0.urdf";
  if (std::filesystem::exists(shared + "/meshes/MANIFEST.tsv")) meshes = shared + "/meshes";
  const char* home = std::getenv("HOME");
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  robot.cache_dir = xdg ? std::string(xdg) + "/medspheres/bench_robot"
                        : std::string(home ? home : ".") + "/.cache/medspheres/bench_robot";
}

void RobotBenchOptions::add_to(Args& args) {
  CLI::App& app = args.app();
  CLI::Option* urdf =
      app.add_option("urdf", robot.urdf, "Robot description")->capture_default_str();
  app.add_option("--robot", generated,
                 "A generated robot instead of a URDF: coarse-arm (7 joints, 11 coarse links)")
      ->check(CLI::IsMember({"coarse-arm"}))
      ->excludes(urdf);
  args.add("--configs", configs, "Seeded joint configurations");
  args.add("--seed", seed, "Seed of the configurations and the scene");
  args.add("--margin", margin, "Collision threshold (m): colliding means distance <= it");
  args.add("--cache", robot.cache_dir, "Folder of cached bakes ('' for none)");
  args.add("--jobs", robot.jobs, "Links baked at once (0: one per core)");
  app.add_option("--package", robot.packages, "PKG=DIR for package:// (repeatable)");
  args.add("--srdf", srdf, "SRDF whose <disable_collisions> pairs are excluded");
  args.add_meshes(meshes);
  app.add_flag("!--no-self", self, "Robot against the scene only");
}

int run_robot_bench(const char* bench, const std::string& generated, const std::string& cache_dir,
                    std::string& urdf, const std::function<int()>& run) {
  const GeneratedRobot robot(generated, cache_dir);
  if (!generated.empty()) urdf = robot.urdf();
  if (!std::filesystem::exists(urdf)) {
    std::fprintf(stderr, "%s: no robot at %s (give a URDF)\n", bench, urdf.c_str());
    return 2;
  }
  try {
    return run();
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: %s\n", bench, e.what());
    return 2;
  } catch (const std::exception& e) {  // a figure the bench checks came out wrong
    std::fprintf(stderr, "%s: %s\n", bench, e.what());
    return 1;
  }
}

}  // namespace medspheres::bench
