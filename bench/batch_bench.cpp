// Batch baking of a generated asset library: meshes per second on this machine's cores,
// the second run's time against a warm cache, and peak memory.
//
// Usage: bench_batch [--count N] [--compare N] [--dir DIR]
//   Writes N meshes (default 1000; boxes, icospheres, tori, capsules, cylinders of 100 to
//   20k triangles, as OFF, binary STL and OBJ in nested folders) under DIR (default: a
//   fresh folder in /tmp, removed at the end), bakes them with the default options and a
//   cache (cold), bakes them again (warm: every mesh copied from the cache), and bakes the
//   first --compare meshes (default 100) without a cache once as parallel single-threaded
//   bakes (--jobs 0, the default) and once one mesh at a time on every core (--jobs 1).
// Target: the warm run at least 50x faster than the cold one.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_timing.h"
#include "medspheres/batch/batch.h"
#include "medspheres/threads.h"
#include "support/mesh_library.h"

namespace {

namespace fs = std::filesystem;
using medspheres::BatchOutcome;
using medspheres::BatchResult;

double peak_mib(int who) {
  rusage u{};
  getrusage(who, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux: KiB
}

using medspheres::bench::cpu_seconds;

struct Run {
  BatchResult result;
  double cpu = 0.0;  ///< CPU seconds it took
};

void row(const char* name, const Run& run, int jobs, int threads) {
  const BatchResult& r = run.result;
  const double n = static_cast<double>(r.rows.size());
  std::printf("%-26s %6zu %6zu %6zu %6zu %4d %7d %9.2f %9.2f %9.2f %11.2f\n", name, r.rows.size(),
              r.count(BatchOutcome::kBaked), r.count(BatchOutcome::kCached),
              r.count(BatchOutcome::kFailed), jobs, threads, r.seconds, n / r.seconds, run.cpu,
              n / run.cpu);
  std::fflush(stdout);
}

Run run(const std::vector<medspheres::BatchInput>& inputs, const std::string& out,
        const std::string& cache, int jobs) {
  medspheres::BatchOptions o;
  o.output_dir = out;
  o.cache_dir = cache;
  o.jobs = jobs;
  o.progress = [](const medspheres::BatchRow&, std::size_t done, std::size_t total) {
    if (done % 100 == 0 || done == total) std::fprintf(stderr, "  %zu/%zu\n", done, total);
  };
  const double cpu0 = cpu_seconds();
  Run r{medspheres::bake_batch(inputs, o), 0.0};
  r.cpu = cpu_seconds() - cpu0;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t count = 1000, compare = 100;
  std::string dir;
  medspheres::bench::Args args("bench_batch", "Batch baking: throughput, warm cache, memory");
  args.add("--count", count, "meshes in the generated library");
  args.add("--compare", compare, "meshes baked again to compare --jobs 0 with --jobs 1");
  args.add("--dir", dir, "work folder (default: a fresh one in /tmp, removed at the end)");
  args.parse(argc, argv);
  const bool temporary = dir.empty();
  if (temporary)
    dir = (fs::temp_directory_path() / ("medspheres-bench-batch-" + std::to_string(::getpid())))
              .string();
  fs::remove_all(dir);

  const auto t0 = medspheres::bench::Clock::now();
  const auto library = medspheres::test::write_mesh_library(dir + "/lib", count);
  std::size_t triangles = 0, smallest = SIZE_MAX, largest = 0;
  for (const auto& m : library) {
    triangles += m.triangles;
    smallest = std::min(smallest, m.triangles);
    largest = std::max(largest, m.triangles);
  }
  std::printf("library: %zu meshes, %zu to %zu triangles (%zu in all), written in %.2f s\n",
              library.size(), smallest, largest, triangles, medspheres::bench::seconds_since(t0));
  const std::vector<medspheres::BatchInput> inputs = medspheres::collect_inputs({dir + "/lib"});
  const int cores = medspheres::thread_count(0);

  std::printf(
      "seconds: wall clock; cpu s: user + system time of the process and its import "
      "children\n(on a loaded machine meshes/s falls, meshes per CPU second does "
      "not)\n");
  std::printf("\n%-26s %6s %6s %6s %6s %4s %7s %9s %9s %9s %11s\n", "run", "inputs", "baked",
              "cached", "failed", "jobs", "threads", "seconds", "meshes/s", "cpu s", "meshes/cpu");
  const Run cold_run = run(inputs, dir + "/out-cold", dir + "/cache", 0);
  row("cold, cache filled", cold_run, cores, 1);
  const Run warm_run = run(inputs, dir + "/out-warm", dir + "/cache", 0);
  row("warm, all from the cache", warm_run, cores, 1);
  const BatchResult& cold = cold_run.result;
  const BatchResult& warm = warm_run.result;

  const std::vector<medspheres::BatchInput> some(
      inputs.begin(), inputs.begin() + static_cast<long>(std::min(compare, inputs.size())));
  if (!some.empty()) {
    row("no cache, --jobs 0", run(some, dir + "/out-jobs0", "", 0), cores, 1);
    row("no cache, --jobs 1", run(some, dir + "/out-jobs1", "", 1), 1, cores);
  }
  std::printf("\nwarm run %.1fx faster than the cold one (target >= 50x)\n",
              cold.seconds / warm.seconds);
  std::printf("peak resident memory: %.1f MiB (this process), %.1f MiB (largest import child)\n",
              peak_mib(RUSAGE_SELF), peak_mib(RUSAGE_CHILDREN));
  if (temporary) fs::remove_all(dir);
  return cold.count(BatchOutcome::kFailed) == 0 ? 0 : 1;
}
