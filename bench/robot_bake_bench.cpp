// A whole robot baked with the defaults of `medspheres robot`, end to end: the URDF read,
// every mesh loaded, every link baked (links in parallel, one job per core) and measured.
// Prints the per-link table (the inner set's spheres and nerr, the covering set's spheres,
// certificate and max protrusion in mm (the URDF's metres), the seconds of the link's bake and of
// its cover) and the total wall clock and CPU time of the process (user + system: the work,
// whatever the load of the machine). Target: the Unitree G1 (40 links) in at most 10 s on 2 cores.
// Then every meshed link's shell fraction (filled_solid.h) and, for each link whose inner
// set was baked on its filled solid, the nerr of the same budget's inner set of its real
// (winding-number) solid beside, baked again here. Target: nerr at most 0.3 against the filled
// solid at 32 spheres. --fill bakes them on the filled solid (RobotBakeOptions::
// fill_thin_shells, as `robot --fill`); without it no link is filled.
//
// Usage: bench_robot_bake [URDF] [--package PKG=DIR]... [--jobs N] [--fill]
//   URDF defaults to ../shared/robots/unitree_g1/g1_29dof_rev_1_0.urdf when present.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "medspheres/mesh/filled_solid.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/robot_bake.h"

namespace {

// User + system CPU seconds of the process so far.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Every meshed link's shell fraction (filled_solid.h); for those baked on their filled
// solid, the nerr of the same budget's inner set of the real (winding-number) solid beside.
void thin_shells(const std::vector<medspheres::LinkSolid>& solids,
                 const medspheres::RobotBakeResult& result, const medspheres::BakeRequest& base) {
  using namespace medspheres;
  std::printf(
      "\nShell fractions (thin below %.2f: the inner set fills the filled solid; target: "
      "nerr <= 0.3 against it at 32 spheres)\n",
      kThinShellFraction);
  std::printf("%-28s %8s %7s %9s %9s %s\n", "link", "fraction", "spheres", "nerr real", "nerr fill",
              "target");
  double test_cpu = 0.0;
  std::size_t tested = 0;
  for (std::size_t i = 0; i < result.links.size(); ++i) {
    const LinkBakeStats& s = result.links[i];
    const LinkSolid& solid = solids[i];
    if (solid.parts.empty() || !s.baked_as.empty()) continue;
    const TriangleMesh mesh = solid.parts.size() == 1 ? solid.parts[0].mesh : solid.placed_mesh();
    const MeshReport report = analyze_mesh(mesh);
    const double cpu0 = cpu_seconds();
    const double fraction = shell_fraction(mesh, report, s.link);
    test_cpu += cpu_seconds() - cpu0;
    ++tested;
    if (s.note.find("filled solid") == std::string::npos) {
      std::printf("%-28s %8.3f\n", s.link.c_str(), fraction);
      continue;
    }
    BakeRequest real = base;
    real.solid = SolidKind::kWinding;
    real.max_spheres = s.budget;
    const BakeOutcome before = bake_mesh(mesh, report, real, s.link);
    std::printf("%-28s %8.3f %7zu %9.4f %9.4f %s\n", s.link.c_str(), fraction, s.spheres,
                before.volume ? before.volume->nerr : std::nan(""), s.nerr,
                s.nerr <= 0.3 && s.spheres <= kDefaultSpheresPerLink ? "met" : "MISSED");
  }
  std::printf("the thin-shell test (shell_fraction) of %zu meshes: %.3f s CPU\n", tested, test_cpu);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace medspheres;
  std::string urdf =
      std::string(MEDSPHERES_SOURCE_DIR) + "/../shared/robots/unitree_g1/g1_29dof_rev_1_0.urdf";
  std::vector<std::string> packages;
  int jobs = 0;
  bool fill = false;
  CLI::App app{"Bake every link of a robot with the robot command's defaults"};
  app.add_option("urdf", urdf, "Robot description")->capture_default_str();
  app.add_option("--package", packages, "PKG=DIR for package:// (repeatable)");
  app.add_option("--jobs", jobs, "Links baked at once (0: one per core)")->capture_default_str();
  app.add_flag("--fill", fill, "bake thin shells' inner sets on their filled solid");
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
  options.fill_thin_shells = fill;
  const RobotBakeResult result = bake_robot(robot, solids, options);
  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("%s: %zu links, jobs %d (%d cores)\n\n", urdf.c_str(), robot.links.size(), jobs,
              static_cast<int>(std::thread::hardware_concurrency()));
  std::printf("%-28s %9s %7s %8s %12s %6s %5s %8s %8s %8s\n", "link", "triangles", "inner", "nerr",
              "kind", "outer", "cert", "prot mm", "seconds", "cover s");
  std::size_t spheres = 0, outer = 0, triangles = 0, certified = 0, covered = 0;
  for (const LinkBakeStats& s : result.links) {
    spheres += s.spheres;
    outer += s.outer_spheres;
    triangles += s.triangles;
    covered += s.outer_spheres > 0;
    certified += s.outer_spheres > 0 && s.outer_certified;
    std::printf("%-28s %9zu %7zu %8.4f %12s %6zu %5s %8.2f %8.3f %8.3f %s%s\n", s.link.c_str(),
                s.triangles, s.spheres, s.nerr, s.nerr_kind.c_str(), s.outer_spheres,
                s.outer_spheres == 0 ? "-"
                : s.outer_certified  ? "yes"
                                     : "NO",
                1000.0 * s.outer_protrusion, s.seconds, s.outer_seconds,
                s.baked_as.empty() ? "" : ("same bake as " + s.baked_as + " ").c_str(),
                s.note.c_str());
  }
  std::printf("%-28s %9zu %7zu %8s %12s %6zu %5s\n\n", "total", triangles, spheres, "", "", outer,
              (std::to_string(certified) + "/" + std::to_string(covered)).c_str());
  std::printf(
      "read URDF and meshes %.3f s, bake %.3f s, end to end %.3f s wall; CPU %.3f s (user + "
      "system)\n",
      load_seconds, result.seconds, total, cpu_seconds());
  thin_shells(solids, result, options.request);
  return 0;
}
