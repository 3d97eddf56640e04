// bench_point_query: the C++ side of bench/python_point_query.py. Times point_distances
// (point_distances.h) of the points in a raw float64 file (n x 3, row-major) against a
// sphere-set file at the identity pose, best of --repeat runs, and prints
//   seconds <best wall-clock seconds of one call>
// and writes the distances (raw float64) to --out, so that the Python benchmark can set its
// own time beside it and check that the answers are the same bits.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_timing.h"
#include "medspheres/io.h"
#include "medspheres/point_distances.h"
#include "medspheres/sphere_tree.h"

int main(int argc, char** argv) {
  using namespace medspheres;
  std::string spheres_path, points_path, out_path;
  int repeat = 5;
  bench::Args args("bench_point_query", "Points against one sphere tree, timed (C++ side)");
  args.app().add_option("--spheres", spheres_path, "Sphere-set file")->required();
  args.app().add_option("--points", points_path, "Raw float64 points, n x 3")->required();
  args.app().add_option("--out", out_path, "Raw float64 distances written here")->required();
  args.add("--repeat", repeat, "Runs; the best is printed");
  args.parse(argc, argv);

  std::vector<double> points;
  {
    std::ifstream raw(points_path, std::ios::binary | std::ios::ate);
    const std::streamsize bytes = raw.tellg();
    raw.seekg(0);
    points.resize(static_cast<std::size_t>(bytes) / sizeof(double));
    raw.read(reinterpret_cast<char*>(points.data()), bytes);
  }
  const std::size_t n = points.size() / 3;
  const SphereTree tree(load_sphere_set(spheres_path));
  std::vector<double> out(n);
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = bench::Clock::now();
    point_distances(tree, Eigen::Isometry3d::Identity(), points.data(), n, out.data());
    best = std::min(best, bench::seconds_since(t0));
  }
  std::ofstream(out_path, std::ios::binary)
      .write(reinterpret_cast<const char*>(out.data()),
             static_cast<std::streamsize>(out.size() * sizeof(double)));
  std::printf("seconds %.9f\n", best);
  return 0;
}
