// A plane between two posed vertex sets (separating_plane.h): exact supports from a ball
// tree over each mesh's vertices, GJK on their difference for the direction, and the
// rounding rule of gap_allowance.h for the proof.

#include "medspheres/fcl/separating_plane.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "medspheres/point_triangle.h"

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>

#include "fcl_geometry_visit.h"
#include "gap_allowance.h"

namespace medspheres::fcl {
namespace {

constexpr std::uint32_t kLeafPoints = 8;
constexpr int kMaxSteps = 24;
constexpr int kCoarseDirections = 128;

// The point of a ball (centre c, radius w) farthest along n, |n| = length: c + (w / length) n.
Eigen::Vector3d reach_of(const Eigen::Vector4d& p, const Eigen::Vector3d& n, double length) {
  return p.w() > 0.0 && length > 0.0 ? Eigen::Vector3d(p.head<3>() + (p.w() / length) * n)
                                     : Eigen::Vector3d(p.head<3>());
}

std::vector<Eigen::Vector3d> vertices_of(const MeshModel& mesh) {
  if (mesh.vertices == nullptr || mesh.num_vertices <= 0)
    throw std::invalid_argument("VertexSupport: the mesh has no vertices");
  return {mesh.vertices, mesh.vertices + mesh.num_vertices};
}

// The point of the segment [a, b] nearest the origin.
Eigen::Vector3d nearest_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d e = b - a;
  const double ee = e.squaredNorm();
  if (!(ee > 0.0)) return a;
  return a + std::clamp(-a.dot(e) / ee, 0.0, 1.0) * e;
}

// GJK's simplex: up to four points of the difference B - A.
struct Simplex {
  std::array<Eigen::Vector3d, 4> w;
  int n = 0;

  // Adds s and returns the point of the simplex's hull nearest the origin, keeping the
  // face of a tetrahedron that holds it; sets inside when the origin lies in the
  // tetrahedron (the hulls then overlap).
  Eigen::Vector3d add(const Eigen::Vector3d& s, bool& inside) {
    w[std::size_t(n++)] = s;
    const Eigen::Vector3d o = Eigen::Vector3d::Zero();
    if (n == 1) return s;
    if (n == 2) return nearest_on_segment(w[0], w[1]);
    if (n == 3) return closest_point_on_triangle(o, w[0], w[1], w[2]);
    static constexpr int face[4][4] = {{1, 2, 3, 0}, {0, 2, 3, 1}, {0, 1, 3, 2}, {0, 1, 2, 3}};
    inside = true;
    Eigen::Vector3d best;
    double best2 = std::numeric_limits<double>::infinity();
    int keep = 0;
    for (int f = 0; f < 4; ++f) {
      const Eigen::Vector3d &a = w[face[f][0]], &b = w[face[f][1]], &c = w[face[f][2]];
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      // The origin and the fourth point on the same side of every face: inside.
      inside = inside && normal.dot(o - a) * normal.dot(w[face[f][3]] - a) > 0.0;
      const Eigen::Vector3d p = closest_point_on_triangle(o, a, b, c);
      if (p.squaredNorm() < best2) best = p, best2 = p.squaredNorm(), keep = f;
    }
    const std::array<Eigen::Vector3d, 4> all = w;
    for (int k = 0; k < 3; ++k) w[std::size_t(k)] = all[std::size_t(face[keep][k])];
    n = 3;
    return best;
  }
};

// n . c + r |n| for a ball (c, r) (a vertex: r = 0), |n| given as length.
double value_along(const Eigen::Vector3d& n, double length, const Eigen::Vector4d& p) {
  return n.x() * p.x() + n.y() * p.y() + n.z() * p.z() + p.w() * length;
}

// The ball tree's walk along n (|n| = length, rounded up): a node is opened when its bound
// (its centre's projection plus its radius) exceeds `floor`, which the visit may raise,
// the child reaching further first; visit(i) sees each point of an opened leaf and returns
// false to stop the walk (walk() then returns false).
template <class Nodes, class Visit>
bool walk(const Nodes& nodes, const Eigen::Vector3d& n, double length, const double& floor,
          Visit&& visit) {
  auto bound = [&](const auto& node) { return n.dot(node.centre) + node.radius * length; };
  std::array<std::uint32_t, 128> stack;
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const auto& node = nodes[stack[--top]];
    if (bound(node) <= floor) continue;
    if (node.left == 0) {
      for (std::uint32_t i = node.begin; i < node.end; ++i)
        if (!visit(i)) return false;
      continue;
    }
    const double l = bound(nodes[node.left]), r = bound(nodes[node.right]);
    const std::uint32_t first = l >= r ? node.left : node.right;
    const std::uint32_t second = l >= r ? node.right : node.left;
    if (std::min(l, r) > floor) stack[top++] = second;
    if (std::max(l, r) > floor) stack[top++] = first;
  }
  return true;
}

enum class Stop { cleared, within, stalled, out_of_steps };

// GJK on the difference B - A from the unit direction u, support(u) giving a point of the
// difference and setting gap (B's least minus A's greatest projection on u): stops when
// the gap clears the margin (u is then its direction), when its point of the difference
// lies within the margin of the origin or the origin inside its simplex (the hulls are
// within the margin), when it no longer progresses (GJK's nearest point: the best gap is
// about the hulls' distance), or after max_steps supports.
template <class Support>
Stop gjk(Support&& support, Eigen::Vector3d& u, const double& gap, double scale, double margin,
         int max_steps) {
  Simplex simplex;
  bool inside = false;
  Eigen::Vector3d v = simplex.add(support(u), inside);
  if (detail::gap_beyond(gap, scale, margin)) return Stop::cleared;
  for (int steps = 1; steps < max_steps; ++steps) {
    const double length = v.norm();
    // v is a point of the hulls' difference: they are within |v| of each other.
    if (!(length > margin)) return Stop::within;
    u = v / length;
    const Eigen::Vector3d s = support(u);
    if (detail::gap_beyond(gap, scale, margin)) return Stop::cleared;
    if (length - gap <= 1e-9 * length) return Stop::stalled;
    v = simplex.add(s, inside);
    if (inside) return Stop::within;
  }
  return Stop::out_of_steps;
}

// support_of's visit: the points whose hull holds each geometry it takes.
struct SupportOf {
  using Result = std::unique_ptr<const VertexSupport>;

  template <class BV>
  Result operator()(const ::fcl::BVHModel<BV>& m) const {
    if (m.getModelType() != ::fcl::BVH_MODEL_TRIANGLES || m.vertices == nullptr ||
        m.num_vertices <= 0)
      return nullptr;
    return std::make_unique<const VertexSupport>(
        std::vector<Eigen::Vector3d>(m.vertices, m.vertices + m.num_vertices));
  }
  Result operator()(const detail::Shape& shape) const {
    const ::fcl::CollisionGeometryd& g = shape.geometry;
    switch (shape.type) {
      case ::fcl::GEOM_BOX: {
        const Eigen::Vector3d h = 0.5 * static_cast<const ::fcl::Boxd&>(g).side;
        std::vector<Eigen::Vector3d> corners;
        for (int k = 0; k < 8; ++k)
          corners.emplace_back(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(),
                               k & 4 ? h.z() : -h.z());
        return std::make_unique<const VertexSupport>(corners);
      }
      case ::fcl::GEOM_SPHERE:
        return std::make_unique<const VertexSupport>(std::vector<Sphere>{
            {Eigen::Vector3d::Zero(), static_cast<const ::fcl::Sphered&>(g).radius}});
      case ::fcl::GEOM_CAPSULE: {
        const auto& c = static_cast<const ::fcl::Capsuled&>(g);
        const Eigen::Vector3d z(0.0, 0.0, 0.5 * c.lz);
        return std::make_unique<const VertexSupport>(
            std::vector<Sphere>{{z, c.radius}, {-z, c.radius}});
      }
      default:
        return nullptr;
    }
  }
#if FCL_HAVE_OCTOMAP
  Result operator()(const ::fcl::OcTreed&) const {
    return nullptr;
  }
#endif
  Result operator()(const detail::Unsupported&) const {
    return nullptr;
  }
};

}  // namespace

std::unique_ptr<const VertexSupport> support_of(const ::fcl::CollisionGeometryd& g) {
  return detail::visit_geometry(g, SupportOf{});
}

VertexSupport::VertexSupport(const MeshModel& mesh) : VertexSupport(vertices_of(mesh)) {}

VertexSupport::VertexSupport(const std::vector<Eigen::Vector3d>& vertices) {
  for (const Eigen::Vector3d& p : vertices) points_.emplace_back(p.x(), p.y(), p.z(), 0.0);
  prepare();
}

VertexSupport::VertexSupport(const std::vector<Sphere>& balls) {
  for (const Sphere& b : balls) {
    if (!(std::isfinite(b.radius) && b.radius >= 0.0))
      throw std::invalid_argument("VertexSupport: a ball's radius is not finite and >= 0");
    points_.emplace_back(b.center.x(), b.center.y(), b.center.z(), b.radius);
  }
  prepare();
}

// Checks the points, keeps each once and builds the tree.
void VertexSupport::prepare() {
  if (points_.empty()) throw std::invalid_argument("VertexSupport: no vertices");
  for (const Eigen::Vector4d& p : points_) {
    if (!p.allFinite()) throw std::invalid_argument("VertexSupport: a vertex is not finite");
    extent_ = std::max(extent_, p.lpNorm<1>());
  }
  auto less = [](const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 4, b.data(), b.data() + 4);
  };
  std::sort(points_.begin(), points_.end(), less);
  points_.erase(std::unique(points_.begin(), points_.end()), points_.end());
  nodes_.reserve(2 * points_.size() / kLeafPoints + 2);
  build(0, static_cast<std::uint32_t>(points_.size()));
  choose_coarse();
}

// The subset of coarse_max_along: every point of a small set, else the extremes along
// kCoarseDirections directions of a Fibonacci lattice on the sphere, each kept once.
void VertexSupport::choose_coarse() {
  std::vector<std::uint32_t> chosen;
  if (points_.size() <= std::size_t(kCoarseDirections)) {
    for (std::uint32_t i = 0; i < points_.size(); ++i) chosen.push_back(i);
  } else {
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    std::uint32_t hint = 0;
    for (int k = 0; k < kCoarseDirections; ++k) {
      const double z = 1.0 - (2.0 * k + 1.0) / kCoarseDirections;
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      max_along({r * std::cos(golden * k), r * std::sin(golden * k), z}, &hint);
      chosen.push_back(hint);
    }
    std::sort(chosen.begin(), chosen.end());
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  }
  coarse_index_ = chosen;
  for (std::uint32_t i : chosen) coarse_.push_back(points_[i]);
}

// Node over points_[begin, end): the box's centre, the farthest point's distance (plus
// its ball's radius) rounded up, and children split at the median of the box's longest
// side.
std::uint32_t VertexSupport::build(std::uint32_t begin, std::uint32_t end) {
  Eigen::Vector3d lo = points_[begin].head<3>(), hi = lo;
  for (std::uint32_t i = begin; i < end; ++i) {
    lo = lo.cwiseMin(points_[i].head<3>());
    hi = hi.cwiseMax(points_[i].head<3>());
  }
  Node node;
  node.centre = 0.5 * (lo + hi);
  double r = 0.0;
  for (std::uint32_t i = begin; i < end; ++i)
    r = std::max(r, (points_[i].head<3>() - node.centre).norm() + points_[i][3]);
  node.radius = r * (1.0 + 1e-14) + 1e-15 * node.centre.lpNorm<1>();
  node.begin = begin;
  node.end = end;
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back(node);
  if (end - begin <= kLeafPoints) return index;
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(
      points_.begin() + begin, points_.begin() + mid, points_.begin() + end,
      [axis](const Eigen::Vector4d& a, const Eigen::Vector4d& b) { return a[axis] < b[axis]; });
  const std::uint32_t left = build(begin, mid);
  const std::uint32_t right = build(mid, end);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

VertexSupport::Extreme VertexSupport::max_along(const Eigen::Vector3d& n,
                                                std::uint32_t* hint) const {
  const double length = n.norm() * (1.0 + 1e-15);
  // The hint's point first: a point near the extreme prunes most of the tree at once.
  std::uint32_t arg = hint != nullptr && *hint < points_.size() ? *hint : 0;
  double best = value_along(n, length, points_[arg]);
  walk(nodes_, n, length, best, [&](std::uint32_t i) {
    const double d = value_along(n, length, points_[i]);
    if (d > best) best = d, arg = i;
    return true;
  });
  if (hint != nullptr) *hint = arg;
  return {best, reach_of(points_[arg], n, length)};
}

bool VertexSupport::at_most(const Eigen::Vector3d& n, double limit, std::uint32_t hint) const {
  const double length = n.norm() * (1.0 + 1e-15);
  if (!(hint < points_.size() && value_along(n, length, points_[hint]) <= limit)) return false;
  return walk(nodes_, n, length, limit,
              [&](std::uint32_t i) { return value_along(n, length, points_[i]) <= limit; });
}

VertexSupport::CoarseExtreme VertexSupport::coarse_max_along(const Eigen::Vector3d& n) const {
  const double length = n.norm() * (1.0 + 1e-15);
  std::size_t arg = 0;
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < coarse_.size(); ++i) {
    const double d = value_along(n, length, coarse_[i]);
    if (d > best) best = d, arg = i;
  }
  return {best, reach_of(coarse_[arg], n, length), coarse_index_[arg]};
}

PlaneResult separated(const VertexSupport& a, const ::fcl::Transform3d& X_WA,
                      const VertexSupport& b, const ::fcl::Transform3d& X_WB, double margin,
                      const Eigen::Vector3d& guess) {
  PlaneResult out;
  if (!std::isfinite(margin) || margin < 0.0 || !X_WA.matrix().allFinite() ||
      !X_WB.matrix().allFinite())
    return out;
  const Eigen::Matrix3d R_A = X_WA.linear(), R_B = X_WB.linear();
  const Eigen::Vector3d p_A = X_WA.translation(), p_B = X_WB.translation();
  const double scale = p_A.lpNorm<1>() + p_B.lpNorm<1>() + a.extent() + b.extent();
  // B's least and A's greatest projection on the unit u, and the points of B - A giving
  // them: exactly (the trees' walks), or over the subsets (the first phase).
  double gap = 0.0;
  std::uint32_t hint_a = 0, hint_b = 0;  // the last extremes: each walk's start
  auto support = [&](const Eigen::Vector3d& u) {
    const VertexSupport::Extreme e_a = a.max_along(R_A.transpose() * u, &hint_a);
    const VertexSupport::Extreme e_b = b.max_along(-(R_B.transpose() * u), &hint_b);
    gap = (u.dot(p_B) - e_b.value) - (e_a.value + u.dot(p_A));
    ++out.steps;
    return Eigen::Vector3d(X_WB * e_b.point - X_WA * e_a.point);
  };
  double top_b = 0.0;  // B's subset's last extreme
  auto coarse_support = [&](const Eigen::Vector3d& u) {
    const VertexSupport::CoarseExtreme e_a = a.coarse_max_along(R_A.transpose() * u);
    const VertexSupport::CoarseExtreme e_b = b.coarse_max_along(-(R_B.transpose() * u));
    top_b = e_b.value;
    gap = (u.dot(p_B) - e_b.value) - (e_a.value + u.dot(p_A));
    hint_a = e_a.index;
    hint_b = e_b.index;
    ++out.coarse_steps;
    return Eigen::Vector3d(X_WB * e_b.point - X_WA * e_a.point);
  };
  auto proved = [&](const Eigen::Vector3d& direction, double proved_gap) {
    out.free = true;
    out.direction = direction;
    out.gap = proved_gap;
    return out;
  };
  Eigen::Vector3d d = guess.allFinite() && guess.squaredNorm() > 0.0 ? guess : p_B - p_A;
  if (!(d.squaredNorm() > 0.0)) d = Eigen::Vector3d::UnitX();
  Eigen::Vector3d u = d.normalized();
  // The subsets' hulls lie in the sets' hulls: within the margin there, within it here.
  const Stop first = gjk(coarse_support, u, gap, scale, margin, kMaxSteps);
  if (first == Stop::within || first == Stop::stalled) {
    out.no_plane = true;
    return out;
  }
  if (first == Stop::cleared) {
    // A's exact extreme along u, and every vertex of B within the slack left: the limit
    // bounds B's computed extreme, so their gap is a gap the proof accepts.
    const Eigen::Vector3d n_b = -(R_B.transpose() * u);
    const double top_a = a.max_along(R_A.transpose() * u, &hint_a).value;
    const double slack =
        (u.dot(p_B) - top_b) - (top_a + u.dot(p_A)) - margin - detail::gap_allowance(scale, margin);
    const double limit_b = top_b + 0.9 * slack;
    const double limited = (u.dot(p_B) - limit_b) - (top_a + u.dot(p_A));
    ++out.steps;
    if (detail::gap_beyond(limited, scale, margin) && b.at_most(n_b, limit_b, hint_b))
      return proved(u, limited);
  }
  // The exact supports from the first phase's direction and extremes.
  if (gjk(support, u, gap, scale, margin, kMaxSteps) != Stop::cleared) return out;
  return proved(u, gap);
}

}  // namespace medspheres::fcl
