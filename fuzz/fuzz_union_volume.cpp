// A structured fuzzer for the exact union volume (bake/union_volume.h) on degenerate ball
// sets: coincident, tangent and nested balls, collinear and coplanar centres, radii from
// 1e-9 to 1e9. The bytes choose a scale and, ball by ball, how it relates to the earlier
// ones. Oracles, each with its tolerance derived below:
// 1. closed forms: one ball, two balls (disjoint, lens, nested: one continuous function of
//    the centre distance);
// 2. bounds that hold for any sets: max_i V_i <= V <= sum_i V_i, and Bonferroni's
//    V >= sum_i V_i - sum_{i<j} V(B_i and B_j), with the pair volumes in closed form;
// 3. seeded Monte Carlo in the bounding box (seed from the bytes, so a failure repeats).
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include "fuzz_support.h"
#include "medspheres/bake/union_volume.h"
#include "support/ball_formulas.h"

namespace {

using Eigen::Vector3d;
using medspheres::Sphere;
using medspheres::test::ball_volume;
using medspheres::test::kPi;
using medspheres::test::lens_volume;
constexpr double kEps = std::numeric_limits<double>::epsilon();

Vector3d direction(FuzzedDataProvider& in) {
  static const Vector3d kAxes[] = {Vector3d::UnitX(),  Vector3d::UnitY(), Vector3d::UnitZ(),
                                   -Vector3d::UnitX(), Vector3d(1, 1, 0), Vector3d(1, 1, 1)};
  const std::uint8_t pick = in.ConsumeIntegral<std::uint8_t>();
  if (pick < 128) return kAxes[pick % 6].normalized();
  Vector3d d(in.ConsumeFloatingPointInRange(-1.0, 1.0), in.ConsumeFloatingPointInRange(-1.0, 1.0),
             in.ConsumeFloatingPointInRange(-1.0, 1.0));
  return d.norm() > 1e-3 ? d.normalized() : Vector3d::UnitZ();
}

// The next ball, placed against the earlier ones as the bytes say.
Sphere next_ball(FuzzedDataProvider& in, const std::vector<Sphere>& balls, double scale) {
  const double r = scale * in.ConsumeFloatingPointInRange(0.05, 2.0);
  const std::size_t n = balls.size();
  const Sphere& a = n ? balls[in.ConsumeIntegralInRange<std::size_t>(0, n - 1)] : Sphere{};
  switch (n ? in.ConsumeIntegralInRange(0, 7) : 0) {
    case 1:  // coincident centre (same radius: a duplicate)
      return {a.center, in.ConsumeBool() ? a.radius : r};
    case 2:  // externally tangent
      return {a.center + (a.radius + r) * direction(in), r};
    case 3: {  // internally tangent or nested
      const double inner = a.radius * in.ConsumeFloatingPointInRange(0.01, 1.0);
      return {a.center + (a.radius - inner) * in.ConsumeProbability<double>() * direction(in),
              inner};
    }
    case 4:  // on the line of the first two centres
      if (n >= 2)
        return {balls[0].center +
                    in.ConsumeFloatingPointInRange(-3.0, 3.0) * (balls[1].center - balls[0].center),
                r};
      break;
    case 5:  // in the plane of the first three centres
      if (n >= 3)
        return {
            balls[0].center +
                in.ConsumeFloatingPointInRange(-2.0, 2.0) * (balls[1].center - balls[0].center) +
                in.ConsumeFloatingPointInRange(-2.0, 2.0) * (balls[2].center - balls[0].center),
            r};
      break;
    case 6:  // a radius anywhere in [1e-9, 1e9], centred on an earlier sphere
      return {a.center + a.radius * direction(in),
              std::pow(10.0, in.ConsumeFloatingPointInRange(-9.0, 9.0))};
    default:
      break;
  }
  return {scale * Vector3d(in.ConsumeFloatingPointInRange(-3.0, 3.0),
                           in.ConsumeFloatingPointInRange(-3.0, 3.0),
                           in.ConsumeFloatingPointInRange(-3.0, 3.0)),
          r};
}

// Volume of the union of two balls as a function of their centre distance d: continuous,
// with |dV/dd| = pi a^2 <= pi min(r)^2 (a the radius of the circle where the spheres meet).
double pair_union_volume(const Sphere& p, const Sphere& q) {
  const double d = (p.center - q.center).norm(), r1 = p.radius, r2 = q.radius;
  const double v1 = ball_volume(r1), v2 = ball_volume(r2);
  if (d >= r1 + r2) return v1 + v2;
  if (d <= std::abs(r1 - r2)) return std::max(v1, v2);
  return v1 + v2 - lens_volume(r1, r2, d);
}

// The error of pair_union_volume from rounding: d and r1 + r2 - d are off by at most
// 8 eps (r1 + r2 + |c1| + |c2|) (the centre difference rounds at the scale of the
// coordinates), times the slope pi min(r)^2; the closed forms themselves add a few eps of
// the ball volumes (64 eps, as the library's own tests allow for one simplex).
double pair_tolerance(const Sphere& p, const Sphere& q) {
  const double rmin = std::min(p.radius, q.radius);
  const double delta = 8 * kEps * (p.radius + q.radius + p.center.norm() + q.center.norm());
  return kPi * rmin * rmin * delta + 64 * kEps * (ball_volume(p.radius) + ball_volume(q.radius));
}

// The library's rounding bound (union_volume.h): a few eps (k + 1) 4 pi r_max^3 per
// k-simplex of K; 16 eps per unit as in its tests.
double library_tolerance(const medspheres::UnionMeasures& m, double rmax) {
  const double weight =
      static_cast<double>(m.vertices + 2 * m.edges + 3 * m.triangles + 4 * m.tetrahedra);
  return 16 * kEps * 4 * kPi * rmax * rmax * rmax * weight;
}

// Monte Carlo in the bounding box B: V ~ |B| k / N, sigma = |B| sqrt(p (1 - p) / N) with p
// floored at 1 / N so that an all-in or all-out estimate keeps a sigma. The check allows
// 6 sigma: a false alarm about once in 5e8 runs.
void check_monte_carlo(const std::vector<Sphere>& balls, double volume, double tolerance,
                       std::uint64_t seed) {
  Eigen::AlignedBox3d box;
  for (const Sphere& b : balls) {
    box.extend(b.center - Vector3d::Constant(b.radius));
    box.extend(b.center + Vector3d::Constant(b.radius));
  }
  const double box_volume = box.volume();
  if (!std::isfinite(box_volume) || box_volume <= 0) return;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int kSamples = 8192;
  int hits = 0;
  for (int s = 0; s < kSamples; ++s) {
    const Vector3d x = box.min() + box.sizes().cwiseProduct(Vector3d(u(rng), u(rng), u(rng)));
    for (const Sphere& b : balls)
      if ((x - b.center).squaredNorm() <= b.radius * b.radius) {
        ++hits;
        break;
      }
  }
  const double p = static_cast<double>(hits) / kSamples;
  const double sigma = box_volume * std::sqrt(std::max(p * (1 - p), 1.0 / kSamples) / kSamples);
  MEDSPHERES_FUZZ_CHECK(std::abs(volume - box_volume * p) <= 6 * sigma + tolerance);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const double scale = std::pow(10.0, in.ConsumeIntegralInRange(-9, 9));
  const int n = in.ConsumeIntegralInRange(1, 8);
  std::vector<Sphere> balls;
  while (static_cast<int>(balls.size()) < n) {
    const Sphere b = next_ball(in, balls, scale);
    if (!b.center.allFinite() || !(b.radius > 0) || !std::isfinite(b.radius)) break;
    balls.push_back(b);
  }
  if (balls.empty()) return 0;

  const medspheres::UnionMeasures m = medspheres::measure_union(balls);
  MEDSPHERES_FUZZ_CHECK(std::isfinite(m.volume) && std::isfinite(m.area) && m.area >= 0);
  double rmax = 0, vmax = 0, vsum = 0;
  for (const Sphere& b : balls) {
    rmax = std::max(rmax, b.radius);
    vmax = std::max(vmax, ball_volume(b.radius));
    vsum += ball_volume(b.radius);
  }
  double tolerance = library_tolerance(m, rmax) + 64 * kEps * vsum;
  double bonferroni = vsum;
  for (std::size_t i = 0; i < balls.size(); ++i)
    for (std::size_t j = i + 1; j < balls.size(); ++j) {
      const double pair = pair_union_volume(balls[i], balls[j]);
      bonferroni -= ball_volume(balls[i].radius) + ball_volume(balls[j].radius) - pair;
      tolerance += pair_tolerance(balls[i], balls[j]);
    }
  MEDSPHERES_FUZZ_CHECK(m.volume >= vmax - tolerance && m.volume <= vsum + tolerance);
  MEDSPHERES_FUZZ_CHECK(m.volume >= bonferroni - tolerance);
  if (balls.size() == 1) MEDSPHERES_FUZZ_CHECK(std::abs(m.volume - vsum) <= tolerance);
  if (balls.size() == 2)
    MEDSPHERES_FUZZ_CHECK(std::abs(m.volume - pair_union_volume(balls[0], balls[1])) <= tolerance);
  std::uint64_t seed = 1469598103934665603ull;
  for (std::size_t k = 0; k < size; ++k) seed = (seed ^ data[k]) * 1099511628211ull;
  check_monte_carlo(balls, m.volume, tolerance, seed);
  return 0;
}
