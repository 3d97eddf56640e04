// Huge inputs: a generated torus of N triangles written as a binary STL, then, each in a
// fresh process so that its peak resident memory is its own: "bake" (load_mesh and
// bake_mesh with the defaults, as `medspheres bake` does) and "eval" (load_mesh, the sphere
// set, FitEvaluator::evaluate and certify_cover, as `medspheres eval` does). The import
// runs in the measured process (isolate_import = false), so the peak counts assimp's
// memory too: an upper bound of what each process of the CLI holds. Prints wall-clock and
// CPU seconds (user + system, all threads: the measure on a shared machine) and peak RSS,
// in all and per million triangles. --profile runs the steps in one process instead and
// prints each step's own peak (the high-water mark is reset between steps).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench_args.h"
#include "medspheres/bake/bake.h"
#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/io.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/measure/self_intersection.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/mesh_io.h"

namespace fs = std::filesystem;
using namespace medspheres;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A torus of major radius 1 and minor 0.4 with about n triangles (2 a b, a = 2.5 b),
// streamed as binary STL. Each vertex is computed once per grid point, so that equal
// corners are bit-identical floats and the mesh welds closed.
std::size_t write_torus_stl(const std::string& path, std::size_t n) {
  const int b = std::max(3, static_cast<int>(std::lround(std::sqrt(n / 5.0))));
  const int a = std::max(3, static_cast<int>(std::lround(2.5 * b)));
  auto point = [&](int i, int j) {
    const double u = 2 * kPi * (i % a) / a, v = 2 * kPi * (j % b) / b;
    const double r = 1.0 + 0.4 * std::cos(v);
    return std::array<float, 3>{static_cast<float>(r * std::cos(u)),
                                static_cast<float>(r * std::sin(u)),
                                static_cast<float>(0.4 * std::sin(v))};
  };
  std::ofstream out(path, std::ios::binary);
  char header[80] = {};
  out.write(header, 80);
  const std::uint32_t count = static_cast<std::uint32_t>(2) * a * b;
  out.write(reinterpret_cast<const char*>(&count), 4);
  auto tri = [&](const std::array<float, 3>& p, const std::array<float, 3>& q,
                 const std::array<float, 3>& r) {
    const float normal[3] = {0, 0, 0};
    const std::uint16_t attr = 0;
    out.write(reinterpret_cast<const char*>(normal), 12);
    for (const auto* c : {&p, &q, &r}) out.write(reinterpret_cast<const char*>(c->data()), 12);
    out.write(reinterpret_cast<const char*>(&attr), 2);
  };
  for (int i = 0; i < a; ++i)
    for (int j = 0; j < b; ++j) {
      const auto p00 = point(i, j), p10 = point(i + 1, j), p11 = point(i + 1, j + 1),
                 p01 = point(i, j + 1);
      tri(p00, p10, p11);
      tri(p00, p11, p01);
    }
  return count;
}

struct Run {
  double seconds = 0;
  double cpu_seconds = 0;  // user + system, of the child and its threads
  double peak_mib = 0;
  bool ok = false;
};

// Runs \p work in a child process; its wall-clock time and peak RSS (wait4).
Run in_child(const std::function<void()>& work) {
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    try {
      work();
      _exit(0);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      _exit(1);
    }
  }
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  Run r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.peak_mib = static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
  const auto sec = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * t.tv_usec;
  };
  r.cpu_seconds = sec(usage.ru_utime) + sec(usage.ru_stime);
  r.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  return r;
}

MeshLoadOptions in_process() {
  MeshLoadOptions o;
  o.isolate_import = false;
  return o;
}

// "VmRSS" or "VmHWM" of this process, in MiB.
double status_mib(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::stod(line.substr(key.size())) / 1024.0;
  return 0.0;
}

// CPU seconds (user + system, all threads) of this process so far.
double process_cpu_seconds() {
  struct rusage u {};
  getrusage(RUSAGE_SELF, &u);
  const auto sec = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return sec(u.ru_utime) + sec(u.ru_stime);
}

// One step of the profile: its CPU seconds, its own peak (the high-water mark is reset
// before it, by writing 5 to /proc/self/clear_refs) and what stays resident after it.
void profile_step(const char* name, double mtri, const std::function<void()>& step) {
  { std::ofstream("/proc/self/clear_refs") << "5"; }
  const double c0 = process_cpu_seconds();
  step();
  const double cpu = process_cpu_seconds() - c0;
  const double peak = status_mib("VmHWM"), rss = status_mib("VmRSS");
  std::printf("%-28s %9.2f %9.0f %9.0f %10.0f\n", name, cpu, peak, rss, peak / mtri);
  std::fflush(stdout);
}

// The steps of bake and eval one after another in one process (--profile).
void profile(const std::string& mesh, double mtri, int threads) {
  std::printf("%-28s %9s %9s %9s %10s\n", "step", "CPU s", "peak MiB", "after MiB", "peak/Mtri");
  std::optional<LoadedMesh> m;
  profile_step("load_mesh", mtri, [&] { m = load_mesh(mesh, in_process()); });
  profile_step("MeshQuery (alone)", mtri, [&] {
    MeshQueryOptions o;
    o.cap_holes = true;
    MeshQuery q(m->mesh, o);
  });
  profile_step("analyze_mesh", mtri, [&] { analyze_mesh(m->mesh); });
  profile_step("find_self_intersections", mtri, [&] { find_self_intersections(m->mesh, threads); });
  std::optional<FitEvaluator> fit;
  profile_step("FitEvaluator", mtri, [&] { fit.emplace(m->mesh, threads); });
  BakeOptions bo;
  bo.threads = threads;
  BakeResult baked;
  profile_step("bake (medial)", mtri, [&] { baked = bake(fit->query(), bo); });
  profile_step("volume_error", mtri, [&] { fit->volume_error(baked.spheres.spheres, threads); });
  FitOptions fo;
  fo.threads = threads;
  profile_step("evaluate", mtri, [&] { fit->evaluate(baked.spheres.spheres, fo); });
  CoverCertificateOptions co;
  co.threads = threads;
  profile_step("certify_cover", mtri, [&] { certify_cover(m->mesh, baked.spheres.spheres, co); });
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> sizes = {1e5, 3e5, 1e6, 3e6};
  std::string dir = fs::temp_directory_path().string();
  int threads = 0;
  bench::Args args("bench_huge_mesh", "Peak memory and time of bake and eval on huge meshes");
  args.add("--triangles", sizes, "Triangle counts (10000000 for the 10^7 point)");
  args.add("--dir", dir, "Folder for the generated STL files (deleted after)");
  args.add("--threads", threads, "Threads (0: all cores)");
  bool profile_steps = false;
  args.app().add_flag(
      "--profile", profile_steps,
      "Instead of the table: each step of bake and eval in one process, with its own "
      "peak RSS (the first of --triangles only)");
  args.parse(argc, argv);
  if (profile_steps) {
    const std::string mesh = (fs::path(dir) / "medspheres-huge.stl").string();
    const std::size_t n = write_torus_stl(mesh, static_cast<std::size_t>(sizes.front()));
    std::printf("%zu triangles\n", n);
    profile(mesh, static_cast<double>(n) / 1e6, threads);
    fs::remove(mesh);
    return 0;
  }

  std::printf("%10s %6s %9s %9s %9s %10s %9s %9s %10s\n", "triangles", "step", "seconds", "CPU s",
              "peak MiB", "CPU s/Mtri", "MiB/Mtri", "spheres", "file MiB");
  for (double size : sizes) {
    const std::string mesh = (fs::path(dir) / "medspheres-huge.stl").string();
    const std::string spheres = (fs::path(dir) / "medspheres-huge.spheres.json").string();
    const std::size_t n = write_torus_stl(mesh, static_cast<std::size_t>(size));
    const double mtri = static_cast<double>(n) / 1e6;
    const double file_mib = static_cast<double>(fs::file_size(mesh)) / (1 << 20);
    const Run bake = in_child([&] {
      const LoadedMesh m = load_mesh(mesh, in_process());
      BakeRequest request;
      request.medial.threads = threads;
      const BakeOutcome out = bake_mesh(m.mesh, m.report, request, mesh);
      save_sphere_set(out.spheres, spheres);
    });
    const std::size_t count = bake.ok ? load_sphere_set(spheres).size() : 0;
    const Run eval = in_child([&] {
      const LoadedMesh m = load_mesh(mesh, in_process());
      const SphereSet set = load_sphere_set(spheres);
      FitOptions options;
      options.threads = threads;
      FitEvaluator(m.mesh, threads).evaluate(set.spheres, options);
      CoverCertificateOptions co;
      co.threads = threads;
      certify_cover(m.mesh, set.spheres, co);
    });
    for (const auto& [name, r] : {std::make_pair("bake", bake), std::make_pair("eval", eval)})
      std::printf("%10zu %6s %9.2f %9.2f %9.0f %10.2f %9.0f %9zu %10.0f%s\n", n, name, r.seconds,
                  r.cpu_seconds, r.peak_mib, r.cpu_seconds / mtri, r.peak_mib / mtri, count,
                  file_mib, r.ok ? "" : "  FAILED");
    std::fflush(stdout);
    fs::remove(mesh);
    fs::remove(spheres);
  }
  return 0;
}
