// A structured fuzzer for the exact union volume (bake/union_volume.h) on degenerate ball
// sets: coincident, tangent and nested balls, collinear and coplanar centres, radii from
// 1e-9 to 1e9. The bytes choose a scale and, ball by ball, how it relates to the earlier
// ones. Oracles, each with its tolerance derived below:
// 1. closed forms: one ball, two balls (disjoint, lens, nested: one continuous function of
//    the centre distance);
// 2. bounds that hold for any sets: max_i V_i <= V <= sum_i V_i, and Bonferroni's
//    V >= sum_i V_i - sum_{i<j} V(B_i and B_j), with the pair volumes in closed form;
//    when no three balls overlap pairwise, that bound is the volume itself (closed form);
// 3. otherwise seeded Monte Carlo in the bounding box (seed from the bytes, so a failure
//    repeats).
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include "fuzz_support.h"
#include "medspheres/measure/union_volume.h"
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

// How far the computed centre distance d and r1 + r2 - d may be off: at most
// 8 eps (r1 + r2 + |c1| + |c2|) (the centre difference rounds at the scale of the
// coordinates).
double distance_rounding(const Sphere& p, const Sphere& q) {
  return 8 * kEps * (p.radius + q.radius + p.center.norm() + q.center.norm());
}

// The error of pair_union_volume from rounding: distance_rounding times the slope
// pi min(r)^2; the closed forms themselves add a few eps of the ball volumes (64 eps, as
// the library's own tests allow for one simplex).
double pair_tolerance(const Sphere& p, const Sphere& q) {
  const double rmin = std::min(p.radius, q.radius);
  return kPi * rmin * rmin * distance_rounding(p, q) +
         64 * kEps * (ball_volume(p.radius) + ball_volume(q.radius));
}

// Whether balls p and q may share interior points: their computed centre distance is
// below r1 + r2 plus its rounding, so that no true overlap is missed.
bool may_overlap(const Sphere& p, const Sphere& q) {
  return (p.center - q.center).norm() < p.radius + q.radius + distance_rounding(p, q);
}

// Whether no three balls pairwise may overlap. Then no point lies inside three balls,
// every term of inclusion-exclusion beyond the pairs is 0, and
// V = sum_i V_i - sum_{i<j} V(B_i and B_j) exactly: Bonferroni's bound is the volume.
bool no_triple_overlap(const std::vector<Sphere>& balls) {
  const std::size_t n = balls.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      if (!may_overlap(balls[i], balls[j])) continue;
      for (std::size_t k = j + 1; k < n; ++k)
        if (may_overlap(balls[i], balls[k]) && may_overlap(balls[j], balls[k])) return false;
    }
  return true;
}

// The library's rounding bound (union_volume.h): a few eps (k + 1) 4 pi r_max^3 per
// k-simplex of K; 16 eps per unit as in its tests.
double library_tolerance(const medspheres::UnionMeasures& m, double rmax) {
  const double weight =
      static_cast<double>(m.vertices + 2 * m.edges + 3 * m.triangles + 4 * m.tetrahedra);
  return 16 * kEps * 4 * kPi * rmax * rmax * rmax * weight;
}

// A uniform double in [0, 1) from 53 random bits (std::uniform_real_distribution takes a
// logarithm on every draw in libstdc++, most of the time of a run here).
double unit(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Monte Carlo in the bounding box B: if V is right, the number k of N uniform samples that
// fall in the union is binomial with mean mu = N V / |B|, and Bernstein's inequality gives
// P(|k - mu| >= t) <= 2 exp(-t^2 / (2 (mu + t / 3))) for any p, however small (a normal
// approximation with sigma from the estimate k / N is not: with mu = 14, three hits put it
// 6 "sigma" off about once in 2000 such inputs). With 2 exp(-L) = 1e-9, L = ln(2e9), the
// check allows t = L / 3 + sqrt(L^2 / 9 + 2 L mu), plus V's tolerance counted in samples.
// The sampling loop uses plain doubles and
// no coverage instrumentation: it is the oracle, whose branches (hit or miss, sample by
// sample) say nothing about the code under test and would only feed libFuzzer noise.
__attribute__((no_sanitize("coverage"))) void check_monte_carlo(const std::vector<Sphere>& balls,
                                                                double volume, double tolerance,
                                                                std::uint64_t seed) {
  Eigen::AlignedBox3d box;
  std::vector<double> xyzr;  // per ball: centre and squared radius
  for (const Sphere& b : balls) {
    box.extend(b.center - Vector3d::Constant(b.radius));
    box.extend(b.center + Vector3d::Constant(b.radius));
    xyzr.insert(xyzr.end(), {b.center.x(), b.center.y(), b.center.z(), b.radius * b.radius});
  }
  const double box_volume = box.volume();
  if (!std::isfinite(box_volume) || box_volume <= 0) return;
  const Vector3d lo = box.min(), size = box.sizes();
  std::mt19937_64 rng(seed);
  constexpr int kSamples = 8192;
  int hits = 0;
  for (int s = 0; s < kSamples; ++s) {
    const double x = lo.x() + size.x() * unit(rng), y = lo.y() + size.y() * unit(rng),
                 z = lo.z() + size.z() * unit(rng);
    for (std::size_t b = 0; b < xyzr.size(); b += 4) {
      const double dx = x - xyzr[b], dy = y - xyzr[b + 1], dz = z - xyzr[b + 2];
      if (dx * dx + dy * dy + dz * dz <= xyzr[b + 3]) {
        ++hits;
        break;
      }
    }
  }
  const double mu = kSamples * volume / box_volume;
  const double L = std::log(2e9);
  const double t = L / 3 + std::sqrt(L * L / 9 + 2 * L * std::max(mu, 0.0));
  MEDSPHERES_FUZZ_CHECK(std::abs(hits - mu) <= t + kSamples * tolerance / box_volume);
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
  // A closed form (one ball, two balls, no triple overlap among the distinct balls: an
  // exact duplicate adds nothing to the union) checks the volume within the rounding
  // tolerance alone, tighter than Monte Carlo's bound on top of it.
  std::vector<Sphere> distinct;
  for (const Sphere& b : balls)
    if (std::none_of(distinct.begin(), distinct.end(),
                     [&](const Sphere& d) { return d.center == b.center && d.radius == b.radius; }))
      distinct.push_back(b);
  if (no_triple_overlap(distinct)) {
    double exact = 0;
    for (const Sphere& b : distinct) exact += ball_volume(b.radius);
    for (std::size_t i = 0; i < distinct.size(); ++i)
      for (std::size_t j = i + 1; j < distinct.size(); ++j)
        exact -= ball_volume(distinct[i].radius) + ball_volume(distinct[j].radius) -
                 pair_union_volume(distinct[i], distinct[j]);
    MEDSPHERES_FUZZ_CHECK(std::abs(m.volume - exact) <= tolerance);
    return 0;
  }
  std::uint64_t seed = 1469598103934665603ull;
  for (std::size_t k = 0; k < size; ++k) seed = (seed ^ data[k]) * 1099511628211ull;
  check_monte_carlo(balls, m.volume, tolerance, seed);
  return 0;
}
