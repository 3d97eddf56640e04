// The volume flow of the covering bake (cover_flow.h).
//
// Objective. For balls (c_j, r_j) the union's volume U, plus
//   sum over elements i of  w_i max(0, v_i)^2 / delta,   v_i = min_j (far_j(i) - r_j),
//   sum over balls j of   A max(0, p_j - cap)^2 / delta,  p_j = r_j - D(c_j),
// far_j(i) the distance from c_j to the farthest point of element i, w_i the area it
// stands for, A the surface's area, D the signed distance to the surface (positive inside).
// Every term is a volume: an element left outside by v adds about w_i v of uncovered volume,
// and the penalty weighs it by v / delta, so that as delta falls (from 1e-2 L to 1e-4 L,
// geometrically) an element left out costs more than any volume it saves.
//
// Gradients. dU/dr_j is the area of ball j's sphere that lies in no other ball, dU/dc_j
// the integral of the outward normal over that area (moving a ball sweeps volume through
// its exposed sphere only); both are estimated on kDirections points of a Fibonacci lattice
// of the sphere. The penalties' gradients are exact: an element's term moves its nearest ball
// (the one of least v) towards its farthest point and grows it; the cap's term shrinks the
// ball and moves it along the gradient of D (from the closest point to the centre, inward).
//
// Steps. Adam (first and second moment decays 0.9 and 0.99) on each ball's (c, r), its step
// kStep L per coordinate at most, so that its moves are in units of the mesh whatever the
// scale of the gradients. Each element's candidate balls are listed: those whose gap to it
// (distance to its farthest point less the radius) is within kMargin L of the least; none for
// an element that some ball holds with more than kMargin L to spare. A ball whose centre and
// radius moved by mu in all changes each gap by at most mu, so the lists stay right (the
// nearest ball listed, an element left out still held) while every ball has moved by at
// most kMargin L / 2 since they were made; then they are made again.
//
// Why a flow and not a search over assignments. The union's volume is a function of the
// balls alone; which ball holds which element follows from where they are. Moving all balls
// at once along the volume's gradient lets a ball give up part of the surface while its
// neighbours take it over, which moves that keep each ball's elements fixed cannot do.
#include "cover_flow.h"

#include "cover_elements.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace medspheres::detail {

namespace {

constexpr int kDirections = 160;
constexpr double kMargin = 3e-2;                         // relative to L
constexpr double kStep = 2e-3;                           // Adam's step, relative to L
constexpr double kDeltaFirst = 1e-2, kDeltaLast = 1e-4;  // relative to L
constexpr double kDecay1 = 0.9, kDecay2 = 0.99;
constexpr long long kBlock = 1024;  // elements per summation block (thread-count independent)

// The signed distance at a ball's centre (probe: the closest-point search from the last
// triangle, the side read again only when the centre moved farther than its distance to
// the surface) and its gradient.
struct Depth {
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  Probe probe;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();

  // Whether a ball (c, r) surely protrudes at most \p cap without a query: from the last
  // probe, D(c) >= D(at) - |c - at| while c stays within half that depth (so that the next
  // update still reads the side from the last one), and a 1e-12 L margin covers rounding.
  bool surely_within(const Eigen::Vector3d& c, double r, double cap, double L) const {
    const double moved = (c - at).norm();
    return probe.triangle >= 0 && moved < 0.5 * probe.depth &&
           r - (probe.depth - moved) <= cap - 1e-12 * L;
  }

  void update(const MeshQuery& query, const Eigen::Vector3d& c) {
    probe = detail::probe(query, c, at, probe);
    at = c;
    const Eigen::Vector3d off = c - probe.closest;
    const double d = off.norm();
    gradient = d > 0.0 ? Eigen::Vector3d((probe.depth > 0.0 ? 1.0 : -1.0) * off / d)
                       : Eigen::Vector3d::Zero();
  }
};

using Gradient = Eigen::Matrix<double, 4, 1>;  // d/dc, d/dr

// The distance from c to the farthest point of element i (of its ball, for a patch), and
// that point.
double farthest_point(const Elements& e, std::size_t i, const Eigen::Vector3d& c,
                      Eigen::Vector3d& p) {
  if (e.patches()) {
    const Eigen::Vector3d off = e.centroids[i] - c;
    const double d = off.norm();
    p = d > 0.0 ? Eigen::Vector3d(e.centroids[i] + e.reach[i] * off / d) : e.centroids[i];
    return d + e.reach[i];
  }
  double far = -1.0;
  for (int q : e.items[i]) {
    const double d = (e.points[static_cast<std::size_t>(q)] - c).squaredNorm();
    if (d > far) far = d, p = e.points[static_cast<std::size_t>(q)];
  }
  return std::sqrt(far);
}

// Each element's candidate balls (file comment), as offsets into one index list.
struct Candidates {
  std::vector<std::size_t> begin;
  std::vector<std::uint32_t> ball;
};

Candidates list_candidates(const Elements& e, const std::vector<Sphere>& balls, double margin,
                           int threads) {
  const std::size_t n = e.size(), k = balls.size();
  std::vector<std::vector<std::uint32_t>> lists(n);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long ii = 0; ii < static_cast<long long>(n); ++ii) {
    const std::size_t i = static_cast<std::size_t>(ii);
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> gap(k);
    for (std::size_t j = 0; j < k; ++j) {
      gap[j] = (e.centroids[i] - balls[j].center).norm() - balls[j].radius;
      best = std::min(best, gap[j] + e.reach[i]);
    }
    // Held with room to spare by some ball: no ball's move in the next iterations uncovers it.
    if (best + margin < 0.0) continue;
    for (std::size_t j = 0; j < k; ++j)
      if (gap[j] - e.reach[i] <= best + margin) lists[i].push_back(static_cast<std::uint32_t>(j));
  }
  Candidates c;
  c.begin.push_back(0);
  for (const auto& l : lists) {
    c.ball.insert(c.ball.end(), l.begin(), l.end());
    c.begin.push_back(c.ball.size());
  }
  return c;
}

// The coverage penalty's gradient (file comment), summed in fixed blocks of elements.
void add_coverage(const Elements& e, const Candidates& cand, const std::vector<Sphere>& balls,
                  double delta, int threads, std::vector<Gradient>& grad) {
  const long long n = static_cast<long long>(e.size());
  const long long blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<Gradient>> part(static_cast<std::size_t>(blocks));
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long b = 0; b < blocks; ++b) {
    std::vector<Gradient>& out = part[static_cast<std::size_t>(b)];
    out.assign(balls.size(), Gradient::Zero());
    for (long long ii = b * kBlock; ii < std::min(n, (b + 1) * kBlock); ++ii) {
      const std::size_t i = static_cast<std::size_t>(ii);
      double least = std::numeric_limits<double>::infinity();
      std::size_t arg = 0;
      Eigen::Vector3d p = Eigen::Vector3d::Zero(), far_point = Eigen::Vector3d::Zero();
      for (std::size_t q = cand.begin[i]; q < cand.begin[i + 1]; ++q) {
        const std::size_t j = cand.ball[q];
        const double v = farthest_point(e, i, balls[j].center, p) - balls[j].radius;
        if (v < least) least = v, arg = j, far_point = p;
      }
      if (!(least > 0.0) || !std::isfinite(least)) continue;  // held, or no candidates
      const double s = 2.0 * e.weight[i] * least / delta;
      const Eigen::Vector3d dir = balls[arg].center - far_point;
      const double len = dir.norm();
      if (len > 0.0) out[arg].head<3>() += s * dir / len;
      out[arg][3] -= s;
    }
  }
  for (const std::vector<Gradient>& p : part)
    for (std::size_t j = 0; j < grad.size(); ++j) grad[j] += p[j];
}

// The union's volume gradient (file comment) for every ball.
void add_volume(const std::vector<Sphere>& balls, const std::vector<Eigen::Vector3d>& dirs,
                int threads, std::vector<Gradient>& grad) {
  const long long k = static_cast<long long>(balls.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long long jj = 0; jj < k; ++jj) {
    const std::size_t j = static_cast<std::size_t>(jj);
    const Sphere& b = balls[j];
    std::vector<std::size_t> near;
    for (std::size_t o = 0; o < balls.size(); ++o) {
      const double reach = b.radius + balls[o].radius;
      if (o != j && (balls[o].center - b.center).squaredNorm() < reach * reach) near.push_back(o);
    }
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    int exposed = 0;
    for (const Eigen::Vector3d& u : dirs) {
      const Eigen::Vector3d x = b.center + b.radius * u;
      bool hidden = false;
      for (std::size_t o : near)
        if ((x - balls[o].center).squaredNorm() < balls[o].radius * balls[o].radius) {
          hidden = true;
          break;
        }
      if (!hidden) normal += u, ++exposed;
    }
    const double patch = 4.0 * M_PI * b.radius * b.radius / static_cast<double>(dirs.size());
    grad[j].head<3>() += patch * normal;
    grad[j][3] += patch * exposed;
  }
}

}  // namespace

std::vector<Eigen::Vector3d> fibonacci_directions(int n) {
  std::vector<Eigen::Vector3d> u;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n, rho = std::sqrt(1.0 - z * z);
    u.emplace_back(rho * std::cos(golden * k), rho * std::sin(golden * k), z);
  }
  return u;
}

std::vector<Sphere> volume_flow(const MeshQuery& query, const Elements& e,
                                std::vector<Sphere> balls, const FlowOptions& o) {
  const std::size_t k = balls.size();
  if (k == 0 || e.size() == 0 || o.iterations <= 0) return balls;
  const double L = query.mesh().bounds().sizes().maxCoeff();
  double area = 0.0;
  for (double w : e.weight) area += w;
  const std::vector<Eigen::Vector3d> dirs = fibonacci_directions(kDirections);
  std::vector<Depth> depth(k);
  std::vector<Gradient> m(k, Gradient::Zero()), v(k, Gradient::Zero());
  const double margin = kMargin * L;
  Candidates cand;
  double moved = std::numeric_limits<double>::infinity();  // by any ball since the lists
  for (int it = 0; it < o.iterations; ++it) {
    const double t = o.iterations > 1 ? static_cast<double>(it) / (o.iterations - 1) : 1.0;
    const double delta = kDeltaFirst * L * std::pow(kDeltaLast / kDeltaFirst, t);
    if (moved > 0.5 * margin) cand = list_candidates(e, balls, margin, o.threads), moved = 0.0;
    std::vector<Gradient> grad(k, Gradient::Zero());
    add_volume(balls, dirs, o.threads, grad);
    add_coverage(e, cand, balls, delta, o.threads, grad);
    if (std::isfinite(o.cap))
      for (std::size_t j = 0; j < k; ++j) {
        if (depth[j].surely_within(balls[j].center, balls[j].radius, o.cap, L)) continue;
        depth[j].update(query, balls[j].center);
        const double p = balls[j].radius - depth[j].probe.depth;
        if (!(p > o.cap)) continue;
        const double s = 2.0 * area * (p - o.cap) / delta;
        grad[j].head<3>() -= s * depth[j].gradient;
        grad[j][3] += s;
      }
    const double c1 = 1.0 - std::pow(kDecay1, it + 1), c2 = 1.0 - std::pow(kDecay2, it + 1);
    double step_max = 0.0;
    for (std::size_t j = 0; j < k; ++j) {
      m[j] = kDecay1 * m[j] + (1.0 - kDecay1) * grad[j];
      v[j] = kDecay2 * v[j] + (1.0 - kDecay2) * grad[j].cwiseProduct(grad[j]);
      Gradient step = Gradient::Zero();
      for (int a = 0; a < 4; ++a) {
        const double s = std::sqrt(v[j][a] / c2);
        if (s > 0.0) step[a] = kStep * L * (m[j][a] / c1) / s;
      }
      const double r = balls[j].radius;
      balls[j].center -= step.head<3>();
      balls[j].radius = std::max(1e-9 * L, r - step[3]);
      step_max = std::max(step_max, step.head<3>().norm() + std::abs(balls[j].radius - r));
    }
    moved += step_max;
  }
  return balls;
}

}  // namespace medspheres::detail
