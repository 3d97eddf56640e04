// Rendering speed (medspheres render) on a generated scene: a torus of about 10^5
// triangles and a set of spheres on its core circle (radius the tube's: the medial set of
// the smooth torus), drawn at a given size in each view, on 1 thread and on all threads.
// Columns: the ray scene's build (MeshQuery's hierarchy, and the SphereTree flattened), the
// ray casting, the PNG encoding, and their sum (the work `medspheres render` does after
// loading its files), with the CLI's default --tolerance (0.005 L), and the CPU seconds of
// those three (all threads: the work on a loaded machine, where wall time is not). Target: at most
// 2 s at 1024x768 on 2 cores.
//
// Usage: bench_render [--size 1024x768] [--triangles 100000] [--spheres 1000] [--repeat 3]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_timing.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/render/png_write.h"
#include "medspheres/render/render.h"
#include "medspheres/threads.h"

namespace {

using namespace medspheres;

constexpr double kMajor = 1.0, kMinor = 0.35;

SphereSet core_spheres(int n) {
  SphereSet set;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * pi * i / n;
    set.spheres.push_back({Eigen::Vector3d(kMajor * std::cos(a), kMajor * std::sin(a), 0), kMinor});
  }
  return set;
}

struct Timing {
  double build = 1e300, cast = 1e300, encode = 1e300, cpu = 0.0;
};

double cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

}  // namespace

int main(int argc, char** argv) {
  using medspheres::bench::seconds_since;
  std::string size = "1024x768";
  int triangles = 100000, spheres = 1000, repeat = 3;
  medspheres::bench::Args args("bench_render", "Rendering speed on a generated torus scene");
  args.add("--size", size, "Image size WIDTHxHEIGHT");
  args.add("--triangles", triangles, "About this many mesh triangles");
  args.add("--spheres", spheres, "Spheres on the torus's core circle");
  args.add("--repeat", repeat, "Runs per row; the fastest is reported");
  args.parse(argc, argv);
  int width = 0, height = 0;
  if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2 || triangles < 8 || spheres < 1 ||
      repeat < 1) {
    std::fprintf(stderr, "bench_render: bad --size, --triangles, --spheres or --repeat\n");
    return 2;
  }
  // 2 m n triangles with m / n = 5 / 4, the tube's segments fewer than the ring's.
  const int n = std::max(2, int(std::lround(std::sqrt(triangles / 2.5))));
  const int m = std::max(3, int(std::lround(1.25 * n)));
  const TriangleMesh mesh = make_torus(kMajor, kMinor, m, n);
  const SphereSet set = core_spheres(spheres);

  std::printf("Rendering a torus of %zu triangles with %d spheres at %dx%d (best of %d)\n",
              mesh.triangles.size(), spheres, width, height, repeat);
  std::printf("%-6s %7s %9s %9s %9s %9s %9s %10s %10s\n", "view", "threads", "build_s", "cast_s",
              "png_s", "total_s", "cpu_s", "uncovered", "protrude");
  const int all = thread_count(0);
  for (render::View view : {render::View::iso, render::View::grid}) {
    for (int threads : {1, all}) {
      Timing best;
      render::PixelCounts counts;
      for (int r = 0; r < repeat; ++r) {
        const double cpu0 = cpu_seconds();
        auto t0 = medspheres::bench::Clock::now();
        const render::RayScene scene(mesh, set, threads);
        const double build = seconds_since(t0);
        render::RenderOptions o;
        o.view = view;
        o.width = width;
        o.height = height;
        o.threads = threads;
        o.protrusion_tolerance = 0.005 * 2.0 * (kMajor + kMinor);  // the CLI's default
        t0 = medspheres::bench::Clock::now();
        const render::Rendering out = render::render(scene, o);
        const double cast = seconds_since(t0);
        t0 = medspheres::bench::Clock::now();
        const std::string png = render::encode_png(out.image);
        const double encode = seconds_since(t0);
        const double cpu = cpu_seconds() - cpu0;
        if (build + cast + encode < best.build + best.cast + best.encode)
          best = {build, cast, encode, cpu};
        counts = out.counts;
      }
      std::printf("%-6s %7d %9.3f %9.3f %9.3f %9.3f %9.3f %10zu %10zu\n",
                  render::to_string(view).c_str(), threads, best.build, best.cast, best.encode,
                  best.build + best.cast + best.encode, best.cpu, counts.uncovered,
                  counts.protruding);
    }
  }
  return 0;
}
