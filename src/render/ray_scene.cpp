#include "medspheres/render/ray_scene.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <utility>

#include <Eigen/Geometry>

#include "medspheres/sphere_tree.h"
#include "medspheres/threads.h"

namespace medspheres::render {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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
    : num_triangles_(mesh.triangles.size()), spheres_(spheres.spheres) {
  const bool parallel = thread_count(threads) >= 2;
  mesh_lo_ = spheres_lo_ = Eigen::Vector3d::Constant(kInf);
  mesh_hi_ = spheres_hi_ = Eigen::Vector3d::Constant(-kInf);
  for (const auto& t : mesh.triangles)
    for (int k : t) grow(mesh_lo_, mesh_hi_, mesh.vertices.at(k), 0.0);
  for (const Sphere& s : spheres_) grow(spheres_lo_, spheres_hi_, s.center, s.radius);
  // MeshQuery's hierarchy takes most of the time: on a thread of its own when allowed;
  // get() rethrows what it threw.
  std::future<void> mesh_done =
      std::async(parallel ? std::launch::async : std::launch::deferred, [this, &mesh] {
        if (!mesh.triangles.empty()) query_ = std::make_unique<const MeshQuery>(mesh);
      });
  flatten_spheres(spheres);
  mesh_done.get();
}

double RayScene::distance_to_mesh(const Eigen::Vector3d& p) const {
  return query_ ? query_->closest_point(p).distance() : kInf;
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

// MeshQuery::cast_ray: the nearest crossing, and with count_crossings every crossing
// before limit, +1 into the solid and -1 out of it.
void RayScene::trace_mesh(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double limit,
                          bool count_crossings, RayHit& hit) const {
  if (!query_) return;
  const RayCrossings c = query_->cast_ray(o, d, limit, count_crossings);
  if (count_crossings) hit.sphere_winding += c.winding;
  if (c.triangle < 0 || !(c.t < hit.mesh_t)) return;
  hit.mesh_t = c.t;
  hit.triangle = c.triangle;
  const auto corner = query_->triangle_corners(c.triangle);
  const Eigen::Vector3d n = (corner[1] - corner[0]).cross(corner[2] - corner[0]).normalized();
  hit.mesh_normal = n.dot(d) > 0.0 ? Eigen::Vector3d(-n) : n;
}

}  // namespace medspheres::render
