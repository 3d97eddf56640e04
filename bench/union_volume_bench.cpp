// Exact union volume (UnionOfBalls) on random ball sets, single thread.
//
// The balls have centres uniform in a cube at one centre per unit volume and radii
// uniform in [0.8 m, 1.2 m]; the mean radius m sets how many neighbours each ball
// overlaps (a ball of radius r overlaps a neighbour at distance below r + r'). "medial"
// (about 8 neighbours) is the density of a sampled medial sphere set; "heavy" (about 30)
// is a deliberately crowded set. Each row is the best of three runs.
//
// A second table does the same for baked sets: per closed classic mesh of
// ../shared/meshes (when present) and the bundled examples, S_D at the default bake and
// S+ dilated as bench_table2 does (cap 0.2%, cover 0.3% of the box's largest side).
//
// Targets: 10^4 balls in at most 0.5 s and 10^5 balls in at most 5 s.
//
// Usage: bench_union_volume [max_n] [--only SUBSTRING]
//   max_n   the largest random set (default 100000)
//   --only  only the baked sets of meshes whose name contains SUBSTRING

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "bench_args.h"
#include "medspheres/bake/bake.h"
#include "medspheres/bake/dilate.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "support/shared_meshes.h"

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

std::vector<medspheres::Sphere> random_balls(int n, double mean_radius, unsigned seed) {
  std::mt19937_64 rng(seed);
  const double side = std::cbrt(static_cast<double>(n));
  std::uniform_real_distribution<double> pos(0.0, side), rad(0.8 * mean_radius, 1.2 * mean_radius);
  std::vector<medspheres::Sphere> balls(n);
  for (auto& b : balls) {
    b.center = {pos(rng), pos(rng), pos(rng)};
    b.radius = rad(rng);
  }
  return balls;
}

// Expected number of overlapping neighbours at unit density: the volume of the ball of
// radius r + r', averaged over the two radii (uniform on [0.8 m, 1.2 m]).
double expected_neighbours(double m) {
  const double lo = 0.8 * m, hi = 1.2 * m;
  const int k = 64;
  double sum = 0.0;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const double r = lo + (hi - lo) * (i + 0.5) / k, s = lo + (hi - lo) * (j + 0.5) / k;
      sum += 4.0 / 3.0 * kPi * std::pow(r + s, 3);
    }
  return sum / (k * k);
}

double mean_radius_for(double neighbours) {
  double lo = 0.01, hi = 10.0;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (expected_neighbours(mid) < neighbours ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The best of three constructions: stage times and measures of the fastest.
struct Timed {
  medspheres::UnionStageSeconds seconds{};
  double total = std::numeric_limits<double>::infinity();
  medspheres::UnionMeasures measures;
};

Timed best_of_three(const std::vector<medspheres::Sphere>& balls) {
  Timed best;
  for (int run = 0; run < 3; ++run) {
    const medspheres::UnionOfBalls u(balls);
    const medspheres::UnionStageSeconds& t = u.stage_seconds();
    const double total = t.triangulation + t.classification + t.measures;
    if (total < best.total) {
      best.total = total;
      best.seconds = t;
      best.measures = u.measures();
    }
  }
  return best;
}

void baked_sets(const std::string& only) {
  const std::vector<medspheres::bench::MeshFile> meshes =
      medspheres::bench::bench_meshes(medspheres::test::shared_meshes_dir(), true);
  std::printf("\nBaked sets: S_D at the default bake, S+ with cap 0.2%% and cover 0.3%% of L\n");
  std::printf("%-34s %-4s %6s %6s %7s %8s %8s %8s %7s\n", "mesh", "set", "balls", "hidden",
              "K.vert", "K.edges", "K.tris", "K.tets", "total s");
  for (const auto& [name, path] : meshes) {
    if (!medspheres::bench::selected(name, only)) continue;
    const medspheres::TriangleMesh mesh = medspheres::load_mesh(path).mesh;
    const medspheres::MeshQuery query(mesh);
    const medspheres::BakeResult sd = medspheres::bake(query);
    const double longest = mesh.bounds().sizes().maxCoeff();
    medspheres::DilateOptions d;
    d.max_protrusion = 0.002 * longest;
    d.cover_tolerance = 0.003 * longest;
    const medspheres::SphereSet splus = medspheres::dilate(query, sd.spheres, d).spheres;
    for (const auto& [set, balls] :
         {std::make_pair("S_D", &sd.spheres.spheres), std::make_pair("S+", &splus.spheres)}) {
      const Timed t = best_of_three(*balls);
      std::printf("%-34s %-4s %6zu %6zu %7zu %8zu %8zu %8zu %7.3f\n", name.c_str(), set,
                  balls->size(), t.measures.hidden.size(), t.measures.vertices, t.measures.edges,
                  t.measures.triangles, t.measures.tetrahedra, t.total);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  int max_n = 100000;
  medspheres::bench::Args args("bench_union_volume",
                               "Exact union volume on random ball sets and on baked sets");
  args.add("max_n", max_n, "largest number of random balls (sizes 1000, 10000, ... up to it)");
  std::string only;
  args.add_only(only)->description("only baked sets of meshes whose name contains SUBSTRING");
  args.parse(argc, argv);
  std::printf(
      "bench_union_volume: exact volume of a union of random balls, one thread, best of 3\n");
  std::printf("%-7s %7s %4s %6s %7s %8s %8s %8s %7s %7s %7s %7s %7s  %s\n", "overlap", "balls",
              "nbrs", "hidden", "K.vert", "K.edges", "K.tris", "K.tets", "tri s", "class s",
              "incl s", "total s", "target", "verdict");
  struct Setting {
    const char* name;
    double neighbours;
  };
  for (const Setting& setting : {Setting{"medial", 8.0}, Setting{"heavy", 30.0}}) {
    const double m = mean_radius_for(setting.neighbours);
    for (int n = 1000; n <= max_n; n *= 10) {
      const std::vector<medspheres::Sphere> balls = random_balls(n, m, 12345u + n);
      const Timed timed = best_of_three(balls);
      const medspheres::UnionStageSeconds& best = timed.seconds;
      const double best_total = timed.total;
      const medspheres::UnionMeasures& meas = timed.measures;
      const double target = n == 10000 ? 0.5 : n == 100000 ? 5.0 : 0.0;
      const std::string verdict = target == 0.0 ? "-" : best_total <= target ? "met" : "MISSED";
      char target_text[16] = "-";
      if (target > 0.0) std::snprintf(target_text, sizeof target_text, "%.1f", target);
      std::printf("%-7s %7d %4.0f %6zu %7zu %8zu %8zu %8zu %7.3f %7.3f %7.3f %7.3f %7s  %s\n",
                  setting.name, n, setting.neighbours, meas.hidden.size(), meas.vertices,
                  meas.edges, meas.triangles, meas.tetrahedra, best.triangulation,
                  best.classification, best.measures, best_total, target_text, verdict.c_str());
    }
  }
  baked_sets(only);
  return 0;
}
