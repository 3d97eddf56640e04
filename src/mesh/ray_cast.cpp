// MeshQuery::cast_ray (mesh_query.h): rays through the 4-wide hierarchy of MeshQuery.
//
// Boxes. A node's child boxes are single precision, rounded outward, in box coordinates
// (x - origin) * box_scale (mesh_bvh.h). The ray o + t d is mapped to the same
// coordinates with the same t: ob + t db, ob = (o - origin) * box_scale, db = d *
// box_scale (scaling by a power of two is exact). Each box is then tested by slabs in
// double precision after widening it by kWiden (relative to the larger of 1 and |ob|),
// far beyond the rounding of ob (one ulp of |o - origin|) and of the slab quotients, so
// a box is culled only when the ray misses it, or enters it beyond the current bound,
// by more than rounding: the triangles the ray crosses all survive, and the answer is
// that of the test over every triangle.
//
// Triangles. Moller-Trumbore, on the corners a, ab = b - a, ac = c - a that MeshQuery
// stores per triangle (QueryTriangle). Its determinant is ab . (d x ac) = -d . n with
// n = ab x ac the outward normal of an outward-wound triangle, so det > 0 means the
// ray enters the solid there. A ray in the triangle's plane (det == 0) crosses nothing.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "medspheres/mesh/mesh_query.h"
#include "mesh_bvh.h"

namespace medspheres {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kWiden = 0x1p-36;

// The crossing of the ray with a triangle at t in [0, limit): its t and determinant,
// or false.
inline bool cross_triangle(const detail::QueryTriangle& tri, const Eigen::Vector3d& o,
                           const Eigen::Vector3d& d, double limit, double& t, double& det) {
  const Eigen::Vector3d p = d.cross(tri.ac);
  det = tri.ab.dot(p);
  if (det == 0.0) return false;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - tri.a;
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const Eigen::Vector3d q = s.cross(tri.ab);
  const double v = d.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  t = tri.ac.dot(q) * inv;
  return t >= 0.0 && t < limit;
}

// The ray in box coordinates, ready for slab tests.
struct BoxRay {
  double o[3], inv[3], widen;
  bool flat[3];  // db[k] == 0: the slab holds the whole ray or none of it

  // Entry t of the widened box of child k (at least 0); +infinity when the ray misses it.
  double entry(const detail::Bvh4Node& n, int k) const {
    double t0 = 0.0, t1 = kInf;
    for (int a = 0; a < 3; ++a) {
      const double lo = double(n.lo[a][k]) - widen, hi = double(n.hi[a][k]) + widen;
      if (!(lo <= hi)) return kInf;  // an empty slot
      if (flat[a]) {
        if (o[a] < lo || o[a] > hi) return kInf;
        continue;
      }
      double ta = (lo - o[a]) * inv[a], tb = (hi - o[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (t0 > t1) return kInf;
    }
    return t0;
  }
};

BoxRay box_ray(const detail::MeshBvh& bvh, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  BoxRay r;
  double reach = 1.0;
  for (int a = 0; a < 3; ++a) {
    r.o[a] = (o[a] - bvh.origin[a]) * bvh.box_scale;
    const double db = d[a] * bvh.box_scale;
    r.flat[a] = db == 0.0;
    r.inv[a] = r.flat[a] ? 0.0 : 1.0 / db;
    reach = std::max(reach, std::abs(r.o[a]));
  }
  r.widen = kWiden * reach;
  return r;
}

}  // namespace

RayCrossings MeshQuery::cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                 double limit, bool count_all) const {
  if (!origin.allFinite() || !direction.allFinite() || direction == Eigen::Vector3d::Zero() ||
      std::isnan(limit))
    throw std::invalid_argument(
        "MeshQuery::cast_ray: the origin and direction must be finite, the direction nonzero "
        "and the limit not NaN");
  const detail::MeshBvh& bvh = impl_->bvh;
  const BoxRay ray = box_ray(bvh, origin, direction);
  RayCrossings out;
  double bound = limit;  // boxes entered at or beyond it are culled
  // Depth-first with the nearest child on top: at most 3 entries per level are pending,
  // and the depth is bounded by the build (mesh_query.cpp: under 48 + log2(n) levels).
  std::pair<std::int32_t, double> stack[512];
  int top = 0;
  stack[top++] = {0, 0.0};
  while (top > 0) {
    const auto [index, entry] = stack[--top];
    if (entry >= bound) continue;
    const detail::Bvh4Node& node = bvh.nodes[static_cast<std::size_t>(index)];
    std::pair<std::int32_t, double> near[4];
    int n = 0;
    for (int k = 0; k < 4; ++k) {
      if (node.child[k] == detail::kEmpty) continue;
      const double t = ray.entry(node, k);
      if (t >= bound) continue;
      if (node.child[k] >= 0) {
        near[n++] = {node.child[k], t};
        continue;
      }
      const auto leaf = static_cast<std::size_t>(~node.child[k]);
      double th = 0.0, det = 0.0;
      if (!cross_triangle(bvh.triangles[leaf], origin, direction, limit, th, det)) continue;
      if (count_all) out.winding += det > 0.0 ? 1 : -1;
      if (th < out.t) {
        out.t = th;
        out.triangle = bvh.original[leaf];
        if (!count_all) bound = th;
      }
    }
    // Farthest first, so that the nearest child is on top of the stack.
    for (int a = 1; a < n; ++a)
      for (int b = a; b > 0 && near[b - 1].second < near[b].second; --b)
        std::swap(near[b - 1], near[b]);
    for (int c = 0; c < n; ++c) stack[top++] = near[c];
  }
  return out;
}

}  // namespace medspheres
