#include "medspheres/render/ray_scene.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <utility>

#include <Eigen/Geometry>

#include "medspheres/mesh/threads.h"
#include "medspheres/sphere_tree.h"
#include "medspheres/triangle_tree.h"

namespace medspheres::render {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Entry distance of the ray into the box [lo, hi] given in the box's own frame (slabs);
// +infinity when it misses or the box lies behind.
double box_entry(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                 const Eigen::Vector3d& hi) {
  double t0 = 0.0, t1 = kInf;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (o[k] < lo[k] || o[k] > hi[k]) return kInf;
      continue;
    }
    const double inv = 1.0 / d[k];
    double a = (lo[k] - o[k]) * inv, b = (hi[k] - o[k]) * inv;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return kInf;
  }
  return t0;
}

// First t >= 0 where the ray enters the ball, or +infinity (d is a unit vector).
double ball_entry(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& c,
                  double r) {
  const Eigen::Vector3d oc = o - c;
  const double b = d.dot(oc);
  const double disc = b * b - (oc.squaredNorm() - r * r);
  if (disc < 0.0) return kInf;
  const double t = -b - std::sqrt(disc);
  return t >= 0.0 ? t : (-b + std::sqrt(disc) >= 0.0 ? 0.0 : kInf);
}

template <class T>
void grow(Eigen::Vector3d& lo, Eigen::Vector3d& hi, const T& p, double r) {
  lo = lo.cwiseMin(p - Eigen::Vector3d::Constant(r));
  hi = hi.cwiseMax(p + Eigen::Vector3d::Constant(r));
}

}  // namespace

RayScene::RayScene(const TriangleMesh& mesh, const SphereSet& spheres, int threads)
    : vertices_(mesh.vertices), triangles_(mesh.triangles), spheres_(spheres.spheres) {
  const bool parallel = thread_count(threads) >= 2;
  mesh_lo_ = spheres_lo_ = Eigen::Vector3d::Constant(kInf);
  mesh_hi_ = spheres_hi_ = Eigen::Vector3d::Constant(-kInf);
  for (const auto& t : triangles_)
    for (int k : t) grow(mesh_lo_, mesh_hi_, vertices_.at(k), 0.0);
  for (const Sphere& s : spheres_) grow(spheres_lo_, spheres_hi_, s.center, s.radius);
  // The TriangleTree takes most of the time: on a thread of its own when allowed; get()
  // rethrows what it threw.
  std::future<void> mesh_done = std::async(parallel ? std::launch::async : std::launch::deferred,
                                           [this, &mesh] { flatten_mesh(mesh); });
  flatten_spheres(spheres);
  if (!triangles_.empty()) query_ = std::make_unique<const MeshQuery>(mesh);
  mesh_done.get();
}

double RayScene::distance_to_mesh(const Eigen::Vector3d& p) const {
  return query_ ? query_->closest_point(p).distance() : kInf;
}

// The TriangleTree's nodes, breadth first, so that siblings are contiguous.
void RayScene::flatten_mesh(const TriangleMesh& mesh) {
  const TriangleTree tree(mesh);
  const std::optional<TargetNode> root = tree.root();
  if (!root) return;
  std::vector<TargetNode> pending{*root};
  boxes_.emplace_back();
  for (std::size_t i = 0; i < pending.size(); ++i) {
    const TargetNode node = pending[i];  // copy: pending grows below
    BoxNode& box = boxes_[i];
    if (node.is_leaf) {
      box.first = -1;
      box.count = static_cast<int>(node.primitive);
      continue;
    }
    box.axis_t = node.bounds.axis.transpose();
    box.corner = node.bounds.corner;
    const double r = node.bounds.radius;
    box.lo = Eigen::Vector3d::Constant(-r);
    box.hi = Eigen::Vector3d(node.bounds.length[0] + r, node.bounds.length[1] + r, r);
    TargetNode children[ProximityTarget::kMaxChildren];
    const int n = tree.children(node, children);
    boxes_[i].first = static_cast<int>(pending.size());
    boxes_[i].count = n;
    for (int c = 0; c < n; ++c) {
      pending.push_back(children[c]);
      boxes_.emplace_back();
    }
  }
}

void RayScene::flatten_spheres(const SphereSet& spheres) {
  if (spheres.spheres.empty()) return;
  const SphereTree tree(spheres);
  balls_.resize(tree.num_nodes());
  for (std::size_t i = 0; i < tree.num_nodes(); ++i) {
    const Sphere b = tree.bounding_ball(i);
    BallNode& node = balls_[i];
    node.center = b.center;
    node.radius = b.radius;
    if (!tree.is_leaf(i)) {
      node.left = static_cast<int>(tree.left_child(i));
      node.right = static_cast<int>(tree.right_child(i));
      continue;
    }
    node.begin = static_cast<int>(leaf_spheres_.size());
    for (std::size_t s : tree.spheres_below(i)) leaf_spheres_.push_back(static_cast<int>(s));
    node.end = static_cast<int>(leaf_spheres_.size());
  }
}

RayHit RayScene::trace(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
  RayHit hit;
  trace_spheres(origin, direction, hit);
  if (std::isfinite(hit.sphere_t)) {
    // Every crossing before the sphere entry counts towards its winding number.
    trace_mesh(origin, direction, hit.sphere_t, true, hit);
    if (hit.triangle >= 0) return hit;
  }
  trace_mesh(origin, direction, kInf, false, hit);
  return hit;
}

void RayScene::trace_spheres(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                             RayHit& hit) const {
  if (balls_.empty()) return;
  std::pair<int, double> stack[512];  // > the depth bound of SphereTree
  int top = 0;
  stack[top++] = {0, ball_entry(o, d, balls_[0].center, balls_[0].radius)};
  while (top > 0) {
    const auto [i, entry] = stack[--top];
    if (entry >= hit.sphere_t) continue;
    const BallNode& node = balls_[i];
    if (node.left < 0) {
      for (int k = node.begin; k < node.end; ++k) {
        const Sphere& s = spheres_[leaf_spheres_[k]];
        const double t = ball_entry(o, d, s.center, s.radius);
        if (t < hit.sphere_t) hit.sphere_t = t, hit.sphere = leaf_spheres_[k];
      }
      continue;
    }
    const double tl = ball_entry(o, d, balls_[node.left].center, balls_[node.left].radius);
    const double tr = ball_entry(o, d, balls_[node.right].center, balls_[node.right].radius);
    // Nearer child on top of the stack; the depth is bounded by the tree's (SphereTree).
    if (tl <= tr) {
      if (tr < hit.sphere_t) stack[top++] = {node.right, tr};
      if (tl < hit.sphere_t) stack[top++] = {node.left, tl};
    } else {
      if (tl < hit.sphere_t) stack[top++] = {node.left, tl};
      if (tr < hit.sphere_t) stack[top++] = {node.right, tr};
    }
  }
  if (hit.sphere >= 0) {
    const Sphere& s = spheres_[hit.sphere];
    hit.sphere_normal = (o + hit.sphere_t * d - s.center).normalized();
  }
}

// Moller-Trumbore. The determinant is -d . n, n = e1 x e2 the outward normal of an
// outward-wound triangle, so det > 0 means the ray enters the solid there.
void RayScene::trace_mesh(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double limit,
                          bool count_crossings, RayHit& hit) const {
  if (boxes_.empty()) return;
  double best = limit;
  std::pair<int, double> stack[512];  // > the depth of a TriangleTree
  int top = 0;
  stack[top++] = {0, 0.0};
  while (top > 0) {
    const auto [i, entry] = stack[--top];
    if (entry >= best) continue;
    const BoxNode& node = boxes_[i];
    if (node.first < 0) {
      const auto& tri = triangles_[node.count];
      const Eigen::Vector3d a = vertices_[tri[0]];
      const Eigen::Vector3d e1 = vertices_[tri[1]] - a, e2 = vertices_[tri[2]] - a;
      const Eigen::Vector3d p = d.cross(e2);
      const double det = e1.dot(p);
      if (det == 0.0) continue;
      const double inv = 1.0 / det;
      const Eigen::Vector3d s = o - a;
      const double u = s.dot(p) * inv;
      if (u < 0.0 || u > 1.0) continue;
      const Eigen::Vector3d q = s.cross(e1);
      const double v = d.dot(q) * inv;
      if (v < 0.0 || u + v > 1.0) continue;
      const double t = e2.dot(q) * inv;
      if (t < 0.0 || t >= limit) continue;
      if (count_crossings) hit.sphere_winding += det > 0.0 ? 1 : -1;
      if (t < hit.mesh_t) {
        hit.mesh_t = t;
        hit.triangle = node.count;
        const Eigen::Vector3d n = e1.cross(e2).normalized();
        hit.mesh_normal = n.dot(d) > 0.0 ? Eigen::Vector3d(-n) : n;
        if (!count_crossings) best = t;
      }
      continue;
    }
    std::pair<int, double> near[ProximityTarget::kMaxChildren];
    int n = 0;
    for (int c = node.first; c < node.first + node.count; ++c) {
      const BoxNode& child = boxes_[c];
      const double t = child.first < 0 ? 0.0
                                       : box_entry(child.axis_t * (o - child.corner),
                                                   child.axis_t * d, child.lo, child.hi);
      if (t < best) near[n++] = {c, t};
    }
    // Farthest first, so that the nearest child is on top of the stack (n is small).
    for (int a = 1; a < n; ++a)
      for (int b = a; b > 0 && near[b - 1].second < near[b].second; --b)
        std::swap(near[b - 1], near[b]);
    for (int c = 0; c < n; ++c) stack[top++] = near[c];
  }
}

}  // namespace medspheres::render
