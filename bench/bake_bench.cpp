// Bake time and quality per mesh, laid out like Table 1 of the paper: triangles,
// resolution, spheres, seconds, the queries spent, and the exact normalized volume
// error nerr of the (internal) spheres.
//
// Usage: bench_bake [--meshes DIR] [--min N] [--max N] [--only SUBSTRING]
//   For each closed mesh of DIR/MANIFEST.tsv (default ../shared/meshes beside the
//   source tree, when present) and the bundled examples, the resolution is the largest
//   giving at most --max spheres (default 500), found by bake_max_spheres; the bake at
//   that resolution is then timed on 2 threads (median of 3) and on 1 thread.
// Target: median bake <= 1.0 s on 2 cores for meshes up to 30k triangles, at a
// resolution giving 200-500 spheres; <= 3 s for the 100k-triangle dragon.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_timing.h"
#include "medspheres/bake/bake.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "support/shared_meshes.h"

namespace {

using medspheres::bench::Clock;

double time_bake(const medspheres::MeshQuery& q, medspheres::BakeOptions o, int repeats,
                 medspheres::BakeResult* last) {
  std::vector<double> t;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = Clock::now();
    *last = medspheres::bake(q, o);
    t.push_back(medspheres::bench::seconds_since(t0));
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir = medspheres::test::shared_meshes_dir();
  std::size_t min_spheres = 200, max_spheres = 500;
  std::string only;
  medspheres::bench::Args args("bench_bake", "Bake time and quality per mesh (paper, Table 1)");
  args.add_meshes(dir);
  args.add("--min", min_spheres, "note the meshes left with fewer spheres than this");
  args.add("--max", max_spheres, "bake at the largest resolution giving at most this many spheres");
  args.add_only(only);
  args.parse(argc, argv);
  const std::vector<medspheres::bench::MeshFile> meshes =
      medspheres::bench::bench_meshes(dir, false);

  std::printf("Medial sphere baking (paper section 3), resolution = largest with <= %zu spheres\n",
              max_spheres);
  std::printf(
      "s(2t): bake seconds on 2 threads (median of 3); s(1t): on 1 thread; cpq/wq: closest-point "
      "and\n"
      "winding-number queries; nerr: exact normalized volume error of the union of the "
      "spheres\n\n");
  std::printf("%-34s %7s %4s %7s %7s %7s %8s %8s %7s  %s\n", "mesh", "tris", "res", "spheres",
              "s(2t)", "s(1t)", "cpq", "wq", "nerr", "note");
  std::vector<double> small_times;
  double dragon = -1;
  for (const medspheres::bench::MeshFile& e : meshes) {
    if (!medspheres::bench::selected(e.name, only)) continue;
    const medspheres::LoadedMesh m = medspheres::load_mesh(e.path);
    const medspheres::MeshQuery q(m.mesh);
    medspheres::BakeOptions o;
    o.resolution = 16;
    const int res = medspheres::bake_max_spheres(q, max_spheres, o).stats.resolution;
    o.resolution = res;
    medspheres::BakeResult r;
    o.threads = 2;
    const double t2 = time_bake(q, o, 3, &r);
    o.threads = 1;
    const double t1 = time_bake(q, o, 1, &r);
    std::string note;
    if (r.spheres.size() < min_spheres)
      note = "below " + std::to_string(min_spheres) + " spheres at every resolution <= the cap";
    const double nerr = medspheres::FitEvaluator(m.mesh).volume_error(r.spheres.spheres).nerr;
    std::printf("%-34s %7zu %4d %7zu %7.3f %7.3f %8llu %8llu %7.4f  %s\n", e.name.c_str(),
                m.mesh.triangles.size(), res, r.spheres.size(), t2, t1,
                static_cast<unsigned long long>(r.stats.closest_point_queries),
                static_cast<unsigned long long>(r.stats.winding_queries), nerr, note.c_str());
    std::fflush(stdout);
    if (m.mesh.triangles.size() <= 30000) small_times.push_back(t2);
    if (e.name.find("dragon") != std::string::npos && m.mesh.triangles.size() >= 100000)
      dragon = t2;
  }
  if (!small_times.empty()) {
    std::sort(small_times.begin(), small_times.end());
    std::printf(
        "\nmeshes <= 30k triangles: median bake %.3f s, max %.3f s on 2 threads (target: median <= "
        "1.0 s)\n",
        small_times[small_times.size() / 2], small_times.back());
  }
  if (dragon >= 0)
    std::printf("100k-triangle dragon: %.3f s on 2 threads (target <= 3 s)\n", dragon);
  std::printf(
      "paper, Table 1 (3.6 GHz Pentium 4): 14-184 s for 108-468 spheres; AMAA 1,515-25,698 s\n");
  return 0;
}
