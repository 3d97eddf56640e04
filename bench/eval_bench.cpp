// Fit metrics of baked sphere sets (medspheres eval), per mesh: the bundled examples and,
// when ../shared/meshes is present, every closed mesh of its MANIFEST.tsv.
//
// Each mesh is baked at the default options, then evaluated with the default FitOptions
// (10^6 Monte-Carlo points, 10^5 surface samples plus every vertex, seed 1) on all cores.
// The first table is the quality of fit, the second where evaluation spends its time.
//
// Usage: bench_eval [--only SUBSTRING]
#include <cstdio>
#include <string>
#include <vector>

#include "bench_args.h"
#include "medspheres/bake/bake.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/mesh_io.h"
#include "support/shared_meshes.h"

namespace {

struct Row {
  std::string name;
  std::size_t triangles = 0;
  double longest = 0.0;  // L, the largest side of the mesh's bounding box
  medspheres::FitReport report;
};

double percent(double v, double length) {
  return 100.0 * v / length;
}

}  // namespace

int main(int argc, char** argv) {
  std::string only;
  medspheres::bench::Args args("bench_eval", "Fit metrics of baked sphere sets per mesh");
  args.add_only(only);
  args.parse(argc, argv);
  const std::vector<medspheres::bench::MeshFile> meshes =
      medspheres::bench::bench_meshes(medspheres::test::shared_meshes_dir(), false);

  const medspheres::FitOptions options;
  std::vector<Row> rows;
  for (const auto& [name, path] : meshes) {
    if (!medspheres::bench::selected(name, only)) continue;
    const medspheres::LoadedMesh loaded = medspheres::load_mesh(path);
    const medspheres::FitEvaluator fit(loaded.mesh);
    const medspheres::BakeResult baked = medspheres::bake(fit.query());
    Row row;
    row.name = name;
    row.triangles = loaded.mesh.triangles.size();
    row.longest = loaded.report.largest_side();
    row.report = fit.evaluate(baked.spheres.spheres, options);
    rows.push_back(std::move(row));
    std::fprintf(stderr, "%s done\n", name.c_str());
  }

  std::printf(
      "Fit of baked sets (default bake), evaluated with %zu Monte-Carlo points and %zu surface "
      "samples + vertices, seed %llu\n",
      options.volume_samples, options.surface_samples,
      static_cast<unsigned long long>(options.seed));
  std::printf(
      "nerr: exact (every set is internal), marked ~ where the mesh intersects itself and nerr is "
      "approximate;\nMC: Monte-Carlo symmetric-difference error / vol(mesh) "
      "with its 95%% Wilson interval;\nprot: largest protrusion; uncovered: distance of surface "
      "points outside the union, absolute and in %% of L (the bbox's largest side)\n\n");
  std::printf("%-34s %6s %5s %8s %-26s %20s %17s %17s %17s\n", "mesh", "tris", "sph", "nerr",
              "MC [95% interval]", "max prot (%L)", "uncov max (%L)", "uncov mean (%L)",
              "uncov p95 (%L)");
  for (const Row& r : rows) {
    const medspheres::FitReport& f = r.report;
    const medspheres::Estimate95& mc = f.monte_carlo.error;
    char interval[64];
    std::snprintf(interval, sizeof interval, "%.4f [%.4f, %.4f]", mc.estimate, mc.lo, mc.hi);
    std::printf(
        "%-34s %6zu %5zu %1s%7.4f %-26s %9.2g (%8.1e) %9.3g (%5.2f) %9.3g (%5.2f) %9.3g (%5.2f)\n",
        r.name.c_str(), r.triangles, f.balls,
        f.volume.kind == medspheres::NerrKind::kApproximate ? "~" : "", f.volume.nerr, interval,
        f.volume.max_protrusion, percent(f.volume.max_protrusion, r.longest), f.coverage.max,
        percent(f.coverage.max, r.longest), f.coverage.mean, percent(f.coverage.mean, r.longest),
        f.coverage.p95, percent(f.coverage.p95, r.longest));
  }

  for (const Row& r : rows)
    for (const std::string& w : r.report.warnings)
      std::printf("warning, %s: %s\n", r.name.c_str(), w.c_str());

  std::printf("\nEvaluation seconds by part (all cores)\n\n");
  std::printf("%-34s %8s %8s %8s %8s %8s %8s\n", "mesh", "union", "protr", "grid", "MC", "coverage",
              "total");
  double total = 0.0;
  for (const Row& r : rows) {
    const medspheres::FitSeconds& s = r.report.seconds;
    total += s.total;
    std::printf("%-34s %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f\n", r.name.c_str(), s.union_volume,
                s.protrusion, s.grid, s.monte_carlo, s.coverage, s.total);
  }
  std::printf("\n%zu meshes, %.2f s of evaluation in all\n", rows.size(), total);
  return 0;
}
