// Exact union volume (UnionOfBalls) on random ball sets, single thread.
//
// The balls have centres uniform in a cube at one centre per unit volume and radii
// uniform in [0.8 m, 1.2 m]; the mean radius m sets how many neighbours each ball
// overlaps (a ball of radius r overlaps a neighbour at distance below r + r'). "medial"
// (about 8 neighbours) is the density of a sampled medial sphere set; "heavy" (about 30)
// is a deliberately crowded set. Each row is the best of three runs.
//
// Targets: 10^4 balls in at most 0.5 s and 10^5 balls in at most 5 s.
//
// Usage: bench_union_volume [max_n]   (default 100000)

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "medspheres/union_volume.h"

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

}  // namespace

int main(int argc, char** argv) {
  const int max_n = argc > 1 ? std::atoi(argv[1]) : 100000;
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
      medspheres::UnionStageSeconds best{};
      double best_total = std::numeric_limits<double>::infinity();
      medspheres::UnionMeasures meas;
      for (int run = 0; run < 3; ++run) {
        const medspheres::UnionOfBalls u(balls);
        const medspheres::UnionStageSeconds& t = u.stage_seconds();
        const double total = t.triangulation + t.classification + t.measures;
        if (total < best_total) {
          best_total = total;
          best = t;
          meas = u.measures();
        }
      }
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
  return 0;
}
