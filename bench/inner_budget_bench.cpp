// The inner set to a sphere budget: bake_inner_budget (medial candidates, then a chosen
// subset of K) against bake_max_spheres (the largest resolution with at most K spheres),
// both measured by the exact nerr of their union (their spheres are inside the solid).
//
// Usage: bench_inner_budget [--meshes DIR] [--only SUBSTRING] [--threads N]
//                           [--ks 2,4,8,...] [--no-amaa] [--no-classic] [--no-today]
//                           [--candidate-factor F] [--samples N] [--swap-passes P] [--verbose]
//   Part 1: the four meshes AMAA (spheretree's medial method, branch 8, depth 3) was run
//   on, at its sphere counts, its Monte-Carlo error beside. The target: lower nerr at no
//   more spheres on each.
//   Part 2: every closed classic mesh of DIR/MANIFEST.tsv (default ../shared/meshes) at
//   each K of --ks (default 2,4,8,16,32,64). Target: at most 1 s per mesh for K <= 64 on
//   2 cores.
// Seconds are wall-clock for the whole call (every bake of the search included), with
// --threads threads (default 2).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "medspheres/bake/bake.h"
#include "medspheres/bake/inner_budget.h"
#include "medspheres/error.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/mesh_io.h"
#include "support/shared_meshes.h"

namespace {

using namespace medspheres;
using Clock = std::chrono::steady_clock;

struct Run {
  std::optional<std::size_t> spheres;  // none: the method found no set
  double nerr = 0.0;
  double seconds = 0.0;
  double cpu = 0.0;    // CPU seconds of the process over the call, every thread
  std::string search;  // resolution:spheres of every bake
};

bool verbose = false;

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

Run run(const FitEvaluator& fit, int threads, const std::function<BakeResult()>& method) {
  Run r;
  const auto t0 = Clock::now();
  const double c0 = cpu_seconds();
  try {
    const BakeResult b = method();
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    r.cpu = cpu_seconds() - c0;
    r.spheres = b.spheres.size();
    for (const SearchStep& s : b.stats.search)
      r.search += " " + std::to_string(s.resolution) + ":" + std::to_string(s.spheres);
    r.nerr = fit.volume_error(b.spheres.spheres, threads).nerr;
  } catch (const InputError&) {
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    r.cpu = cpu_seconds() - c0;
  }
  if (verbose) std::printf("  search%s\n", r.search.c_str());
  return r;
}

std::string cell(const Run& r) {
  char b[80];
  if (!r.spheres)
    std::snprintf(b, sizeof b, "%5s %7s %6.2f %6.2f", "-", "-", r.seconds, r.cpu);
  else
    std::snprintf(b, sizeof b, "%5zu %7.4f %6.2f %6.2f", *r.spheres, r.nerr, r.seconds, r.cpu);
  return b;
}

struct Both {
  Run today, budget;
};

InnerBudgetOptions budget_options;
bool no_today = false;

Both compare(const FitEvaluator& fit, std::size_t k, int threads) {
  BakeOptions o;
  o.threads = threads;
  Both out;
  if (!no_today) out.today = run(fit, threads, [&] { return bake_max_spheres(fit.query(), k, o); });
  out.budget =
      run(fit, threads, [&] { return bake_inner_budget(fit.query(), k, o, budget_options); });
  return out;
}

struct Amaa {
  const char* file;
  std::size_t spheres;
  double error;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_inner_budget: the inner set to a sphere budget"};
  std::string dir = test::shared_meshes_dir(), only;
  int threads = 2;
  std::vector<std::size_t> ks = {2, 4, 8, 16, 32, 64};
  bool no_amaa = false, no_classic = false;
  app.add_option("--meshes", dir, "folder with MANIFEST.tsv");
  app.add_option("--only", only, "only meshes whose name contains this");
  app.add_option("--threads", threads, "threads")->check(CLI::Range(1, kMaxThreads));
  app.add_option("--ks", ks, "budgets of part 2")->delimiter(',');
  app.add_flag("--no-amaa", no_amaa, "skip part 1");
  app.add_flag("--no-classic", no_classic, "skip part 2");
  app.add_flag("--verbose", verbose, "print the resolutions each call baked");
  app.add_flag("--no-today", no_today, "skip bake_max_spheres");
  app.add_option("--candidate-factor", budget_options.candidate_factor,
                 "InnerBudgetOptions::candidate_factor");
  app.add_option("--samples", budget_options.samples, "InnerBudgetOptions::samples");
  app.add_option("--swap-passes", budget_options.swap_passes, "InnerBudgetOptions::swap_passes");
  CLI11_PARSE(app, argc, argv);
  if (dir.empty()) {
    std::fprintf(stderr, "bench_inner_budget: no shared meshes (--meshes DIR)\n");
    return 2;
  }
  std::printf("Inner set to a budget K: today = bake_max_spheres, budget = bake_inner_budget\n");
  std::printf(
      "nerr: exact normalized volume error; s: wall-clock seconds of the call on %d threads;\n"
      "cpu: CPU seconds of the call, all threads (on a loaded machine, cpu / threads bounds what\n"
      "the wall clock would read unloaded)\n\n",
      threads);
  if (!no_amaa) {
    const Amaa amaa[] = {{"cgal/ellipsoid.off", 485, 0.0206},
                         {"cgal/knot1.off", 502, 0.0345},
                         {"odedstein/torus.obj", 505, 0.0128},
                         {"odedstein/spot_low_resolution.obj", 474, 0.0546}};
    std::printf("Part 1: at AMAA's sphere counts (AMAA: spheretree medial, branch 8, depth 3)\n");
    std::printf("%-34s %5s | %5s %7s | %5s %7s %6s %6s | %5s %7s %6s %6s | %s\n", "mesh", "K",
                "AMAA", "err", "today", "nerr", "s", "cpu", "budg", "nerr", "s", "cpu", "target");
    for (const Amaa& a : amaa) {
      if (!only.empty() && std::string(a.file).find(only) == std::string::npos) continue;
      const FitEvaluator fit(load_mesh(dir + "/" + a.file).mesh, threads);
      const Both b = compare(fit, a.spheres, threads);
      const bool met =
          b.budget.spheres && *b.budget.spheres <= a.spheres && b.budget.nerr < a.error;
      std::printf("%-34s %5zu | %5zu %7.4f | %s | %s | %s\n", a.file, a.spheres, a.spheres, a.error,
                  cell(b.today).c_str(), cell(b.budget).c_str(), met ? "met" : "MISSED");
      std::fflush(stdout);
    }
    std::printf("\n");
  }
  if (!no_classic) {
    std::printf("Part 2: closed classic meshes at small budgets\n");
    std::printf("%-34s %5s | %5s %7s %6s %6s | %5s %7s %6s %6s\n", "mesh", "K", "today", "nerr",
                "s", "cpu", "budg", "nerr", "s", "cpu");
    double worst = 0.0, worst_cpu = 0.0;
    std::string worst_at, worst_cpu_at;
    for (const test::SharedMesh& m : test::read_manifest(dir)) {
      if (!m.closed || !m.classic()) continue;
      if (!only.empty() && m.file.find(only) == std::string::npos) continue;
      const FitEvaluator fit(load_mesh(m.path).mesh, threads);
      for (std::size_t k : ks) {
        const Both b = compare(fit, k, threads);
        std::printf("%-34s %5zu | %s | %s\n", m.file.c_str(), k, cell(b.today).c_str(),
                    cell(b.budget).c_str());
        std::fflush(stdout);
        if (k > 64) continue;
        const std::string at = m.file + " at K = " + std::to_string(k);
        if (b.budget.seconds > worst) {
          worst = b.budget.seconds;
          worst_at = at;
        }
        if (b.budget.cpu > worst_cpu) {
          worst_cpu = b.budget.cpu;
          worst_cpu_at = at;
        }
      }
    }
    std::printf(
        "\nslowest bake_inner_budget call for K <= 64: %.2f s wall (%s), %.2f s CPU (%s); "
        "target <= 1 s wall on 2 cores\n",
        worst, worst_at.c_str(), worst_cpu, worst_cpu_at.c_str());
  }
  return 0;
}
