// Every mesh of ../shared/meshes (MANIFEST.tsv, closed or not) and of ../shared/robots
// (every mesh file under a robot's folder), baked as `medspheres bake MESH` bakes it (the
// defaults), one at a time: the solid used, the spheres, the wall-clock seconds, or the
// error. The target: every mesh that encloses a volume bakes, each in under 1 s.
// Columns: the input's triangles; the solid baked and, for the robust solid, its grid
// resolution and the triangles of its boundary; the spheres and their nerr against that
// solid; wall-clock seconds and CPU seconds (user + system of every thread, and of the
// import child): on a shared machine the wall clock grows with the load, CPU time does not.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_timing.h"
#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/error.h"
#include "support/shared_meshes.h"

namespace fs = std::filesystem;
using namespace medspheres;

namespace {

bool mesh_extension(std::string ext) {
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const char* e : {".stl", ".obj", ".ply", ".off", ".dae", ".gltf", ".glb"})
    if (ext == e) return true;
  return false;
}

// The mesh files under DIR's robot folders, sorted by path.
std::vector<bench::MeshFile> robot_meshes(const std::string& dir) {
  std::vector<bench::MeshFile> out;
  if (dir.empty() || !fs::is_directory(dir)) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && mesh_extension(e.path().extension().string()))
      out.push_back({fs::relative(e.path(), dir).string(), e.path().string()});
  std::sort(out.begin(), out.end(),
            [](const bench::MeshFile& a, const bench::MeshFile& b) { return a.path < b.path; });
  return out;
}

// "robust n=R t=T" for a robust bake (its grid resolution and boundary triangles).
std::string solid_text(const BakeOutcome& out) {
  if (out.solid != SolidKind::kRobust) return to_string(out.solid);
  const auto& x = out.record.extra_stats;
  auto number = [&](const char* key) {
    const auto it = x.find(key);
    return it == x.end() ? std::string("?") : std::to_string(static_cast<long>(it->second));
  };
  return "robust n=" + number("robust_resolution") + " t=" + number("robust_triangles");
}

}  // namespace

int main(int argc, char** argv) {
  std::string meshes = test::shared_meshes_dir();
  std::string robots = meshes.empty() ? "" : (fs::path(meshes).parent_path() / "robots").string();
  std::string only;
  int threads = 0;
  bench::Args args("bench_every_mesh", "Bake every shared mesh and robot mesh with the defaults");
  args.add_meshes(meshes);
  args.add("--robots", robots, "Folder of robot descriptions (every mesh file under it)");
  args.add_only(only);
  args.add("--threads", threads, "Threads of each bake (0: all cores)");
  args.parse(argc, argv);

  std::vector<bench::MeshFile> files;
  if (!meshes.empty())
    for (const test::SharedMesh& m : test::read_manifest(meshes)) files.push_back({m.file, m.path});
  for (bench::MeshFile& f : robot_meshes(robots)) files.push_back({"robots/" + f.name, f.path});

  std::printf("%-46s %9s %-22s %8s %8s %8s %8s  %s\n", "mesh", "triangles", "solid", "spheres",
              "nerr", "wall s", "cpu s", "result");
  int baked = 0, under_wall = 0, under_cpu = 0, failed = 0;
  double worst_wall = 0.0, worst_cpu = 0.0;
  for (const bench::MeshFile& f : files) {
    if (!bench::selected(f.name, only)) continue;
    BakeRequest request;
    request.medial.threads = threads;
    std::vector<std::string> warnings;
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = bench::cpu_seconds();
    try {
      const BakeOutcome out = bake_file(f.path, request, &warnings);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double c = bench::cpu_seconds() - c0;
      ++baked;
      under_wall += s < 1.0;
      under_cpu += c < 1.0;
      worst_wall = std::max(worst_wall, s);
      worst_cpu = std::max(worst_cpu, c);
      const double nerr = out.volume ? out.volume->nerr : -1.0;
      std::printf("%-46s %9zu %-22s %8zu %8.4f %8.3f %8.3f  %s\n", f.name.c_str(),
                  out.record.source.report.triangles, solid_text(out).c_str(), out.spheres.size(),
                  nerr, s, c, s < 1.0 ? "ok" : (c < 1.0 ? "ok cpu" : "SLOW"));
    } catch (const std::exception& e) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ++failed;
      std::printf("%-46s %9s %-22s %8s %8s %8.3f %8.3f  error: %s\n", f.name.c_str(), "-", "-", "-",
                  "-", s, bench::cpu_seconds() - c0, e.what());
    }
  }
  std::printf(
      "\n%d baked (%d in under 1 s wall, slowest %.3f s; %d in under 1 CPU s, most %.3f CPU s), "
      "%d refused\n",
      baked, under_wall, worst_wall, under_cpu, worst_cpu, failed);
  return 0;
}
