#include "medspheres/mesh/cover_certificate.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>

#include "medspheres/sphere_tree.h"
#include "medspheres/threads.h"

namespace medspheres {

namespace {

constexpr double kU = std::numeric_limits<double>::epsilon() / 2.0;  // unit roundoff 2^-53

// Rounding of a piece corner. A corner is p = w0 a + w1 b + w2 c with exact dyadic weights
// w_j >= 0, sum 1 (k / 2^depth, depth <= 30). Computed as fl(fl(w0 a) + fl(w1 b) + fl(w2 c))
// per coordinate (three roundings at most; a fused multiply-add only removes some), the
// standard bound gives |p~_k - p_k| <= gamma_3 sum_j w_j |x_jk| <= gamma_3 A, with A the
// largest |coordinate| of the three corners and gamma_3 = 3u / (1 - 3u). Over three
// coordinates |p~ - p| <= sqrt(3) gamma_3 A < 5.2 u A <= 2^-50 A = 8 u A; the product by
// 2^-50 is exact (a power of two, barring underflow, which only makes the test stricter
// through the absolute term of ball_contains_certainly). Corners of an unsplit triangle
// are the mesh's own vertices: the weights (1, 0, 0) give them exactly, error 0.
double corner_error(double max_abs_coordinate, int depth) {
  return depth == 0 ? 0.0 : 8.0 * kU * max_abs_coordinate;
}

// Candidate balls for triangles: a uniform grid over the mesh's box; each ball is listed in
// the cells its (slightly inflated) box overlaps. Missing a ball here could only cost a
// certificate, never give a wrong one: every containment is tested exactly below.
class BallGrid {
 public:
  BallGrid(const Eigen::AlignedBox3d& box, const std::vector<Sphere>& balls) : box_(box) {
    const Eigen::Vector3d size = box.sizes().cwiseMax(1e-300);
    const double cells = std::clamp(8.0 * static_cast<double>(balls.size()), 1.0, 32768.0);
    const double h = std::max(std::cbrt(size.prod() / cells), size.maxCoeff() / 64.0);
    for (int k = 0; k < 3; ++k) {
      dims_[k] = std::clamp(static_cast<int>(std::ceil(size[k] / h)), 1, 64);
      inv_[k] = dims_[k] / size[k];
    }
    cells_.resize(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2]);
    for (std::size_t i = 0; i < balls.size(); ++i) {
      const double r = balls[i].radius * (1.0 + 1e-9);
      const Eigen::Vector3d lo = balls[i].center.array() - r, hi = balls[i].center.array() + r;
      if ((hi.array() < box.min().array()).any() || (lo.array() > box.max().array()).any())
        continue;
      for_cells(lo, hi, [&](std::size_t c) { cells_[c].push_back(static_cast<int>(i)); });
    }
  }

  // Balls whose boxes meet the cells of [lo, hi], ascending.
  void query(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>& out) const {
    out.clear();
    for_cells(lo, hi,
              [&](std::size_t c) { out.insert(out.end(), cells_[c].begin(), cells_[c].end()); });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

 private:
  template <class F>
  void for_cells(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, F&& f) const {
    int a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = std::clamp(static_cast<int>(std::floor((lo[k] - box_.min()[k]) * inv_[k])), 0,
                        dims_[k] - 1);
      b[k] = std::clamp(static_cast<int>(std::floor((hi[k] - box_.min()[k]) * inv_[k])), 0,
                        dims_[k] - 1);
    }
    for (int x = a[0]; x <= b[0]; ++x)
      for (int y = a[1]; y <= b[1]; ++y)
        for (int z = a[2]; z <= b[2]; ++z)
          f((static_cast<std::size_t>(x) * dims_[1] + y) * dims_[2] + z);
  }

  Eigen::AlignedBox3d box_;
  int dims_[3] = {1, 1, 1};
  double inv_[3] = {1, 1, 1};
  std::vector<std::vector<int>> cells_;
};

// A piece: barycentric weights of its three corners (rows), exact dyadic numbers.
struct Piece {
  Eigen::Matrix3d w;
  int depth = 0;
};

struct TriangleResult {
  bool certified = false;
  bool proven_uncovered = false;
  int depth = 0;
  std::size_t pieces = 0;
  std::vector<CoverPiece> uncertified;
};

class TriangleCertifier {
 public:
  TriangleCertifier(const std::vector<Sphere>& balls, const BallGrid& grid, int max_depth)
      : balls_(balls), grid_(grid), max_depth_(max_depth) {}

  TriangleResult run(int t, const std::array<Eigen::Vector3d, 3>& v) {
    TriangleResult res;
    Eigen::Matrix3d x;  // corners as columns
    for (int k = 0; k < 3; ++k) x.col(k) = v[static_cast<std::size_t>(k)];
    const double a = x.cwiseAbs().maxCoeff();
    grid_.query(x.rowwise().minCoeff(), x.rowwise().maxCoeff(), candidates_);
    stack_.clear();
    stack_.push_back({Eigen::Matrix3d::Identity(), 0});
    while (!stack_.empty()) {
      const Piece piece = stack_.back();
      stack_.pop_back();
      ++res.pieces;
      std::array<Eigen::Vector3d, 3> p;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d wk = piece.w.row(k).transpose();
        p[static_cast<std::size_t>(k)] = x.col(0) * wk[0] + x.col(1) * wk[1] + x.col(2) * wk[2];
      }
      const double e = corner_error(a, piece.depth);
      if (covered(p, e)) {
        res.depth = std::max(res.depth, piece.depth);
        continue;
      }
      const bool out = outside(p, e, a);
      if (piece.depth == max_depth_ || out) {
        res.proven_uncovered = out;
        res.uncertified.push_back({t, p});
        if (res.proven_uncovered) break;  // the triangle is certainly not covered
        continue;
      }
      split(piece);
    }
    res.certified = res.uncertified.empty();
    return res;
  }

 private:
  // Some candidate ball holds the three corners, each within error e.
  bool covered(const std::array<Eigen::Vector3d, 3>& p, double e) {
    const Eigen::Vector3d lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
    const Eigen::Vector3d hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
    auto holds = [&](int i) {
      const Sphere& b = balls_[static_cast<std::size_t>(i)];
      // A ball far from the piece's box cannot hold it (a cheap rejection).
      const Eigen::Vector3d d = (lo - b.center).cwiseMax(Eigen::Vector3d::Zero()) +
                                (b.center - hi).cwiseMax(Eigen::Vector3d::Zero());
      if (d.squaredNorm() > b.radius * b.radius) return false;
      return ball_contains_certainly(b, p[0], e) && ball_contains_certainly(b, p[1], e) &&
             ball_contains_certainly(b, p[2], e);
    };
    if (last_ >= 0 && holds(last_)) return true;
    for (int i : candidates_)
      if (i != last_ && holds(i)) {
        last_ = i;
        return true;
      }
    return false;
  }

  // A corner lies outside every candidate ball by more than rounding: the piece is
  // certainly not covered (every ball that can contain a point of the triangle is a
  // candidate, the grid lists balls by inflated boxes).
  bool outside(const std::array<Eigen::Vector3d, 3>& p, double e, double a) const {
    for (const Eigen::Vector3d& q : p) {
      bool out = true;
      for (int i : candidates_) {
        const Sphere& b = balls_[static_cast<std::size_t>(i)];
        const double margin = e + 1e-12 * (a + b.center.cwiseAbs().maxCoeff() + b.radius);
        if ((q - b.center).norm() <= b.radius + margin) {
          out = false;
          break;
        }
      }
      if (out) return true;
    }
    return false;
  }

  // The four pieces of the midpoint split; the corner piece of each corner, then the middle.
  void split(const Piece& piece) {
    const Eigen::Vector3d w0 = piece.w.row(0), w1 = piece.w.row(1), w2 = piece.w.row(2);
    const Eigen::Vector3d m01 = 0.5 * (w0 + w1), m12 = 0.5 * (w1 + w2), m20 = 0.5 * (w2 + w0);
    auto push = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
      Piece child;
      child.w.row(0) = a;
      child.w.row(1) = b;
      child.w.row(2) = c;
      child.depth = piece.depth + 1;
      stack_.push_back(child);
    };
    push(m01, m12, m20);
    push(m20, m12, w2);
    push(m01, w1, m12);
    push(w0, m01, m20);
  }

  const std::vector<Sphere>& balls_;
  const BallGrid& grid_;
  int max_depth_;
  std::vector<int> candidates_;
  std::vector<Piece> stack_;
  int last_ = -1;
};

void check_inputs(const TriangleMesh& mesh, const std::vector<Sphere>& balls,
                  const CoverCertificateOptions& o) {
  check_threads(o.threads);
  if (o.max_depth < 0 || o.max_depth > 30)
    throw std::invalid_argument("max_depth must be in [0, 30], got " + std::to_string(o.max_depth));
  if (!(o.worst_tolerance >= 0.0) || !std::isfinite(o.worst_tolerance))
    throw std::invalid_argument("worst_tolerance must be finite and >= 0");
  for (const Eigen::Vector3d& v : mesh.vertices)
    if (!v.allFinite()) throw std::invalid_argument("certify_cover: mesh has a non-finite vertex");
  for (const auto& t : mesh.triangles)
    for (int i : t)
      if (i < 0 || static_cast<std::size_t>(i) >= mesh.vertices.size())
        throw std::invalid_argument("certify_cover: mesh has a vertex index out of range");
  SphereSet set;
  set.spheres = balls;
  validate_sphere_set(set, "sphere set");
}

// One piece of the worst-point search: the distance at the centroid and the bound; its
// corners are the mesh triangle's own (corners < 0) or those of pieces[corners], so that
// the whole triangles the search starts from, one per uncertified triangle, take 24 bytes
// each rather than the 96 of three corners.
struct SearchPiece {
  double bound = 0.0;
  std::size_t order = 0;  // tie-break: first made first
  int triangle = -1;
  int corners = -1;
  bool operator<(const SearchPiece& o) const {
    return bound != o.bound ? bound < o.bound : order > o.order;
  }
};

// Best-first maximisation of the distance to the union over the uncertified triangles (see
// the header): dist is 1-Lipschitz, so a piece's points are within f(centroid) + (largest
// centroid-corner distance) of the union.
void search_worst(const TriangleMesh& mesh, const std::vector<Sphere>& balls, double tolerance,
                  std::size_t max_evaluations, CoverCertificate& cert) {
  SphereSet set;
  set.spheres = balls;
  const SphereTree tree(set);
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  std::priority_queue<SearchPiece> queue;
  std::vector<std::array<Eigen::Vector3d, 3>> pieces;  // corners of the split pieces
  std::size_t made = 0;
  auto dist = [&](const Eigen::Vector3d& q, int t) {
    ++cert.worst_evaluations;
    const double d = std::max(0.0, distance(tree, identity, q).distance);
    if (cert.worst_triangle < 0 || d > cert.worst_distance) {
      cert.worst_distance = d;
      cert.worst_point = q;
      cert.worst_triangle = t;
    }
    return d;
  };
  auto push = [&](const std::array<Eigen::Vector3d, 3>& p, int t, bool whole) {
    const Eigen::Vector3d g = (p[0] + p[1] + p[2]) / 3.0;
    double reach = 0.0;
    for (const Eigen::Vector3d& q : p) reach = std::max(reach, (q - g).norm());
    int corners = -1;
    if (!whole) {
      corners = static_cast<int>(pieces.size());
      pieces.push_back(p);
    }
    queue.push({dist(g, t) + reach * (1.0 + 1e-12), made++, t, corners});
  };
  auto corners_of = [&](const SearchPiece& s) -> std::array<Eigen::Vector3d, 3> {
    if (s.corners >= 0) return pieces[static_cast<std::size_t>(s.corners)];
    const auto t = static_cast<std::size_t>(s.triangle);
    return {mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)};
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (cert.triangle_certified[t]) continue;
    const int ti = static_cast<int>(t);
    std::array<Eigen::Vector3d, 3> p = {mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)};
    for (const Eigen::Vector3d& q : p) dist(q, ti);
    push(p, ti, true);
  }
  while (!queue.empty() && queue.top().bound > cert.worst_distance + tolerance &&
         cert.worst_evaluations + 4 <= max_evaluations) {
    const SearchPiece top = queue.top();
    queue.pop();
    const std::array<Eigen::Vector3d, 3> p = corners_of(top);
    const Eigen::Vector3d m01 = 0.5 * (p[0] + p[1]), m12 = 0.5 * (p[1] + p[2]),
                          m20 = 0.5 * (p[2] + p[0]);
    for (const Eigen::Vector3d& q : {m01, m12, m20}) dist(q, top.triangle);
    push({p[0], m01, m20}, top.triangle, false);
    push({m01, p[1], m12}, top.triangle, false);
    push({m20, m12, p[2]}, top.triangle, false);
    push({m01, m12, m20}, top.triangle, false);
  }
  cert.worst_bound = std::max(cert.worst_distance, queue.empty() ? 0.0 : queue.top().bound);
}

// Triangles certified per block (certify_cover).
constexpr std::size_t kCertifyBlock = std::size_t{1} << 16;

}  // namespace

// The test. With q = p~ - c, computed d_k = fl(p~_k - c_k) = q_k (1 + d), each square and
// each of the two additions one more rounding: s~ = fl(sum d_k^2) lies within (1 +- u)^5 of
// |q|^2, so |q| <= sqrt(s~) (1 - u)^-5/2, and the computed root, one more rounding, gives
// |q| <= fl(sqrt(s~)) (1 + 4u) (for u = 2^-53 these products are below 1 + 3.5u + O(u^2)).
// The exact point p is within e of p~, so |p - c| <= fl(sqrt(s~)) (1 + 4u) + e. The
// bound B = fl(fl(fl(sqrt(s~)) + e) (1 + 16u)) is at least (fl(sqrt(s~)) + e)(1 - u)^2 (1 +
// 16u) >= (fl(sqrt(s~)) + e)(1 + 13u), which exceeds that. (1 + 16u = 1 + 2^-49 is a
// double.) These relative bounds hold while no d_k^2 underflows harmfully, i.e. unless
// |q| < about 1e-150; the absolute term 1e-150 covers that case. An overflow gives an
// infinite s~ and a false answer; non-finite input gives false. So B <= r implies that the
// closed ball holds every point within e of p~.
bool ball_contains_certainly(const Sphere& ball, const Eigen::Vector3d& p, double position_error) {
  const double dx = p.x() - ball.center.x(), dy = p.y() - ball.center.y(),
               dz = p.z() - ball.center.z();
  const double s = dx * dx + dy * dy + dz * dz;
  const double bound = (std::sqrt(s) + position_error) * (1.0 + 16.0 * kU) + 1e-150;
  return bound <= ball.radius;
}

CoverCertificate certify_cover(const TriangleMesh& mesh, const std::vector<Sphere>& balls,
                               const CoverCertificateOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check_inputs(mesh, balls, options);
  CoverCertificate cert;
  const std::size_t n = mesh.triangles.size();
  cert.triangles = n;
  cert.triangle_certified.assign(n, 0);
  if (n == 0 || balls.empty()) {
    cert.uncertified_triangles = n;
    cert.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return cert;
  }
  Eigen::AlignedBox3d box;
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) box.extend(mesh.corner(t, k));
  const BallGrid grid(box, balls);
  // A block of triangles at a time, each block's results folded in triangle order before
  // the next: the certificate of one pass over all triangles, while the results (with the
  // pieces of uncertified triangles, nearly every triangle for an inner set) are held for
  // kCertifyBlock triangles only, not per triangle of the mesh.
  const int threads = thread_count(options.threads);
  std::vector<TriangleResult> results;
  for (std::size_t first = 0; first < n; first += kCertifyBlock) {
    const std::size_t last = std::min(n, first + kCertifyBlock);
    results.assign(last - first, TriangleResult{});
    const long long begin = static_cast<long long>(first), end = static_cast<long long>(last);
#pragma omp parallel num_threads(threads)
    {
      TriangleCertifier certifier(balls, grid, options.max_depth);
#pragma omp for schedule(dynamic, 64)
      for (long long t = begin; t < end; ++t) {
        const std::size_t ti = static_cast<std::size_t>(t);
        results[ti - first] = certifier.run(
            static_cast<int>(t), {mesh.corner(ti, 0), mesh.corner(ti, 1), mesh.corner(ti, 2)});
      }
    }
    for (std::size_t t = first; t < last; ++t) {
      TriangleResult& r = results[t - first];
      cert.pieces_tested += r.pieces;
      cert.triangle_certified[t] = r.certified ? 1 : 0;
      if (r.certified) {
        cert.max_depth_reached = std::max(cert.max_depth_reached, r.depth);
        continue;
      }
      ++cert.uncertified_triangles;
      if (r.proven_uncovered) ++cert.proven_uncovered_triangles;
      cert.uncertified_pieces_total += r.uncertified.size();
      for (CoverPiece& p : r.uncertified)
        if (cert.uncertified_pieces.size() < options.max_pieces_reported)
          cert.uncertified_pieces.push_back(std::move(p));
    }
  }
  cert.certified = cert.uncertified_triangles == 0;
  if (!cert.certified) {
    const double tol =
        options.worst_tolerance > 0.0 ? options.worst_tolerance : 1e-4 * box.sizes().maxCoeff();
    search_worst(mesh, balls, tol, options.max_worst_evaluations, cert);
  }
  cert.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cert;
}

}  // namespace medspheres
