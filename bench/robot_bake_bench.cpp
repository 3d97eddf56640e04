// A whole robot baked with the defaults of `medspheres robot`, end to end: the URDF read,
// every mesh loaded, every link baked (links in parallel, one job per core) and measured.
// Prints the per-link table and the total wall clock. Target: the Unitree G1 (40 links)
// in at most 10 s on 2 cores.
//
// Usage: bench_robot_bake [URDF] [--package PKG=DIR]... [--jobs N]
//   URDF defaults to ../shared/robots/unitree_g1/g1_29dof_rev_1_0.urdf when present.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "medspheres/bake/robot_bake.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"

int main(int argc, char** argv) {
  using namespace medspheres;
  std::string urdf =
      std::string(MEDSPHERES_SOURCE_DIR) + "/../shared/robots/unitree_g1/g1_29dof_rev_1_0.urdf";
  std::vector<std::string> packages;
  int jobs = 0;
  CLI::App app{"Bake every link of a robot with the robot command's defaults"};
  app.add_option("urdf", urdf, "Robot description")->capture_default_str();
  app.add_option("--package", packages, "PKG=DIR for package:// (repeatable)");
  app.add_option("--jobs", jobs, "Links baked at once (0: one per core)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (!std::filesystem::exists(urdf)) {
    std::fprintf(stderr, "no robot at %s (give a URDF)\n", urdf.c_str());
    return 2;
  }

  const auto start = std::chrono::steady_clock::now();
  UrdfReadOptions read;
  for (const std::string& p : packages) add_package_dir(read.packages, p);
  const UrdfRobot robot = read_urdf(urdf, read);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  const double load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RobotBakeOptions options;
  options.jobs = jobs;
  options.budget.per_link = kDefaultSpheresPerLink;  // the robot command's default
  const RobotBakeResult result = bake_robot(robot, solids, options);
  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("%s: %zu links, jobs %d (%d cores)\n\n", urdf.c_str(), robot.links.size(), jobs,
              static_cast<int>(std::thread::hardware_concurrency()));
  std::printf("%-28s %9s %8s %10s %12s %8s\n", "link", "triangles", "spheres", "nerr", "kind",
              "seconds");
  std::size_t spheres = 0, triangles = 0;
  for (const LinkBakeStats& s : result.links) {
    spheres += s.spheres;
    triangles += s.triangles;
    std::printf("%-28s %9zu %8zu %10.4f %12s %8.3f %s%s\n", s.link.c_str(), s.triangles, s.spheres,
                s.nerr, s.nerr_kind.c_str(), s.seconds,
                s.baked_as.empty() ? "" : ("same bake as " + s.baked_as + " ").c_str(),
                s.note.c_str());
  }
  std::printf("%-28s %9zu %8zu\n\n", "total", triangles, spheres);
  std::printf("read URDF and meshes %.3f s, bake %.3f s, end to end %.3f s\n", load_seconds,
              result.seconds, total);
  return 0;
}
