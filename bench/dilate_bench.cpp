// Conservative dilation (paper section 5.1): time, sphere counts, and what it buys and
// costs, per mesh.
//
// Usage: bench_dilate [--meshes DIR] [--max N] [--only SUBSTRING]
//   For the bundled examples and each closed classic mesh of DIR/MANIFEST.tsv (default
//   ../shared/meshes beside the source tree, when present): bake S_D at the largest
//   resolution giving at most --max spheres (default 1000), then dilate it with the
//   paper's rule (default options), timed on 2 threads, median of 3. For S_D and S+ the
//   table gives the largest and the mean distance of the surface outside the union
//   (100,000 area-weighted samples plus every vertex) and the largest protrusion, all
//   in % of L, the bounding box's largest side. A last block repeats the dilation with
//   a protrusion cap and cover rounds (0.5% of L each) for comparison.
// Target: dilation <= 0.5 s for sets of up to 1,000 spheres on meshes of up to 30k
// triangles (the paper: 1-5 s).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_timing.h"
#include "medspheres/bake/bake.h"
#include "medspheres/bake/dilate.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/mesh_io.h"
#include "support/shared_meshes.h"

namespace {

using namespace medspheres;

struct Measures {
  double uncovered_max = 0, uncovered_mean = 0, protrusion = 0;
};

Measures measure(const FitEvaluator& fit, const TriangleMesh& mesh, const SphereSet& set,
                 double L) {
  const SurfaceSamples samples = sample_surface(mesh, 100000, 7);
  const CoverageStats c = summarize_coverage(samples, point_coverage(set.spheres, samples.points));
  const VolumeError v = fit.volume_error(set.spheres);
  return {100 * c.max / L, 100 * c.mean / L, 100 * v.max_protrusion / L};
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t max_spheres = 1000;
  std::string dir = test::shared_meshes_dir(), only;
  bench::Args args("bench_dilate", "Conservative dilation (paper section 5.1) per mesh");
  args.add_meshes(dir);
  args.add("--max", max_spheres,
           "bake S_D at the largest resolution giving at most this many spheres");
  args.add_only(only);
  args.parse(argc, argv);
  const std::vector<bench::MeshFile> meshes = bench::bench_meshes(dir, true);

  std::printf(
      "Dilation (paper section 5.1): S_D baked with at most %zu spheres, dilated with the "
      "paper's rule\n",
      max_spheres);
  std::printf(
      "unc max/mean: surface outside the union, %% of L; prot: largest protrusion, %% of L\n\n");
  std::printf("%-32s %6s %5s %5s %6s %6s %6s %6s %8s | %7s %7s %6s | %7s %7s %6s\n", "mesh", "tris",
              "S_D", "S+", "vpts", "grown", "added", "capped", "sec(2t)", "SD max", "SD mean",
              "SD prt", "S+ max", "S+ mean", "S+ prt");
  std::vector<double> in_scope;
  struct Later {
    std::string name;
    TriangleMesh mesh;
    SphereSet sd;
  };
  std::vector<Later> later;
  for (const auto& [name, path] : meshes) {
    if (!bench::selected(name, only)) continue;
    const TriangleMesh mesh = load_mesh(path).mesh;
    const FitEvaluator fit(mesh);
    const MeshQuery& q = fit.query();
    const double L = mesh.bounds().sizes().maxCoeff();
    BakeOptions bo;
    bo.resolution = 24;
    const SphereSet sd = bake_max_spheres(q, max_spheres, bo).spheres;
    DilateOptions o;
    o.threads = 2;
    std::vector<double> t;
    DilateResult d;
    for (int i = 0; i < 3; ++i) {
      const auto t0 = bench::Clock::now();
      d = dilate(q, sd, o);
      t.push_back(bench::seconds_since(t0));
    }
    std::sort(t.begin(), t.end());
    const Measures a = measure(fit, mesh, sd, L), b = measure(fit, mesh, d.spheres, L);
    std::printf(
        "%-32s %6zu %5zu %5zu %6zu %6zu %6zu %6zu %8.3f | %7.3f %7.4f %6.3f | %7.3f %7.4f %6.3f\n",
        name.c_str(), mesh.triangles.size(), sd.size(), d.spheres.size(),
        d.stats.v_points + d.stats.edge_points, d.stats.grown, d.stats.added_vertex,
        d.stats.capped_points, t[1], a.uncovered_max, a.uncovered_mean, a.protrusion,
        b.uncovered_max, b.uncovered_mean, b.protrusion);
    std::fflush(stdout);
    if (mesh.triangles.size() <= 30000 && sd.size() <= 1000) in_scope.push_back(t[1]);
    later.push_back({name, mesh, sd});
  }
  if (!in_scope.empty())
    std::printf(
        "\nsets <= 1000 spheres on meshes <= 30k triangles: max %.3f s, median %.3f s on 2 "
        "threads (target <= 0.5 s; the paper: 1-5 s)\n",
        *std::max_element(in_scope.begin(), in_scope.end()), in_scope[in_scope.size() / 2]);

  std::printf("\nWith a protrusion cap and cover rounds, both 0.5%% of L:\n");
  std::printf("%-32s %5s %5s %6s %6s %6s %7s %8s | %7s %7s %6s\n", "mesh", "S_D", "S+", "vertex",
              "cover", "rounds", "reached", "sec(2t)", "S+ max", "S+ mean", "S+ prt");
  for (const Later& l : later) {
    const FitEvaluator fit(l.mesh);
    const double L = l.mesh.bounds().sizes().maxCoeff();
    DilateOptions o;
    o.threads = 2;
    o.max_protrusion = 0.005 * L;
    o.cover_tolerance = 0.005 * L;
    const DilateResult d = dilate(fit.query(), l.sd, o);
    const Measures b = measure(fit, l.mesh, d.spheres, L);
    std::printf("%-32s %5zu %5zu %6zu %6zu %6d %7s %8.3f | %7.3f %7.4f %6.3f\n", l.name.c_str(),
                l.sd.size(), d.spheres.size(), d.stats.added_vertex, d.stats.added_cover,
                d.stats.cover_rounds, d.stats.cover_reached ? "yes" : "no", d.stats.seconds,
                b.uncovered_max, b.uncovered_mean, b.protrusion);
    std::fflush(stdout);
  }
  return 0;
}
