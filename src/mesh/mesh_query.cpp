// MeshQuery (mesh_query.h): a 4-wide bounding volume hierarchy over the triangles, with
// exact leaf tests by the point-triangle kernel (medspheres/point_triangle.h).
//
// Closest point. The hierarchy prunes only boxes that are provably farther than the best
// triangle found so far: its boxes are single precision, scaled to the mesh's size and
// rounded outward, and pruning allows a slack of 8 float ulps (see closest()); every
// surviving triangle goes through the kernel in double precision, after the cheaper
// plane bound (TrianglePlane). Far queries: once the float boxes no longer tell
// triangles apart, the search visits most of the tree (docs/benchmarks.md gives it), and
// when |p - centre| + the mesh's size exceeds 2^200 it is a brute-force search in
// coordinates scaled by a power of two (closest_far), so that every finite query point
// gets a finite distance and a valid triangle.
//
// Winding numbers (winding_number.cpp). A subtree whose triangles all lie within radius
// r of their area-weighted centre c is replaced by its Taylor expansion to second order
// when |p - c| > beta r; otherwise its triangles' solid angles (Van Oosterom and
// Strackee) are summed directly. The error of one expanded subtree falls like beta^-5
// and errors of different subtrees add up (docs/benchmarks.md: measured totals).
//
// Hole caps. An open mesh's solid is where its winding number exceeds 1/2; across a
// planar hole the boundary of that solid is the hole itself, which a fan from the
// centroid covers exactly when the hole is convex. With the caps, distances to the
// solid's boundary include the holes.
#include "medspheres/mesh/mesh_query.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "medspheres/mesh/mesh_report.h"
#include "medspheres/threads.h"
#include "mesh_bvh.h"

namespace medspheres {

namespace detail {

namespace {

// ---------------------------------------------------------------------------------
// Binary build: binned surface-area heuristic, one triangle per leaf.

struct BinaryNode {
  Eigen::AlignedBox3d box;
  int left = -1, right = -1;  // children, or -1 for a leaf
  int triangle = -1;          // leaf: index into mesh.triangles
  double area() const {
    const Eigen::Vector3d d = box.sizes();
    return 2.0 * (d.x() * d.y() + d.y() * d.z() + d.z() * d.x());
  }
};

class BinaryBuilder {
 public:
  BinaryBuilder(const std::vector<Eigen::AlignedBox3d>& boxes,
                const std::vector<Eigen::Vector3d>& centroids)
      : boxes_(boxes), centroids_(centroids) {}

  std::vector<BinaryNode> build() {
    std::vector<int> ids(boxes_.size());
    std::iota(ids.begin(), ids.end(), 0);
    nodes_.reserve(2 * ids.size());
    recurse(ids, 0, ids.size(), 0);
    return std::move(nodes_);
  }

 private:
  // Beyond this depth the object median is used, which bounds the total depth by
  // kSahDepth + log2(n) whatever the input (a long row of triangles, say).
  static constexpr int kSahDepth = 48;
  static constexpr int kBins = 16;

  int recurse(std::vector<int>& ids, std::size_t b, std::size_t e, int depth) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Eigen::AlignedBox3d box, cbox;
    for (std::size_t i = b; i < e; ++i) {
      box.extend(boxes_[ids[i]]);
      cbox.extend(centroids_[ids[i]]);
    }
    nodes_[index].box = box;
    if (e - b == 1) {
      nodes_[index].triangle = ids[b];
      return index;
    }
    int axis;
    cbox.sizes().maxCoeff(&axis);
    const double lo = cbox.min()[axis], width = cbox.sizes()[axis];
    // A width that overflows (centroids near +-DBL_MAX) cannot be binned: median split.
    const bool binned = depth < kSahDepth && width > 0.0 && std::isfinite(width);
    std::size_t mid = binned ? sah_split(ids, b, e, axis, lo, width) : e;
    if (mid == e) mid = median_split(ids, b, e, axis);
    const int l = recurse(ids, b, mid, depth + 1);
    const int r = recurse(ids, mid, e, depth + 1);
    nodes_[index].left = l;
    nodes_[index].right = r;
    return index;
  }

  // Bins the centroids of ids[b, e) along the axis (lo and width: their extent there) and
  // partitions them at the split of least surface-area cost; returns where the second part
  // starts, or e when no split leaves both parts non-empty.
  std::size_t sah_split(std::vector<int>& ids, std::size_t b, std::size_t e, int axis, double lo,
                        double width) const {
    // kBins * (c - lo) overflows for c - lo beyond DBL_MAX / kBins: clamp before converting.
    auto bin_of = [&](int id) {
      const double x = kBins * (centroids_[id][axis] - lo) / width;
      return x < kBins ? (x > 0.0 ? static_cast<int>(x) : 0) : kBins - 1;
    };
    std::size_t count[kBins] = {};
    Eigen::AlignedBox3d bin_box[kBins];
    for (std::size_t i = b; i < e; ++i) {
      const int k = bin_of(ids[i]);
      ++count[k];
      bin_box[k].extend(boxes_[ids[i]]);
    }
    const int best_k = cheapest_split(count, bin_box);
    if (best_k < 0) return e;
    auto it = std::partition(ids.begin() + b, ids.begin() + e,
                             [&](int id) { return bin_of(id) < best_k; });
    return static_cast<std::size_t>(it - ids.begin());
  }

  // The bin k whose split (bins below k, the rest) costs least, area times count on each
  // side; -1 when every split leaves a side empty.
  static int cheapest_split(const std::size_t (&count)[kBins],
                            const Eigen::AlignedBox3d (&bin_box)[kBins]) {
    double right_area[kBins];
    std::size_t right_count[kBins];
    Eigen::AlignedBox3d acc;
    std::size_t n = 0;
    for (int k = kBins - 1; k > 0; --k) {
      acc.extend(bin_box[k]);
      n += count[k];
      right_area[k] = acc.isEmpty() ? 0.0 : BinaryNode{acc}.area();
      right_count[k] = n;
    }
    double best = std::numeric_limits<double>::infinity();
    int best_k = -1;
    acc.setEmpty();
    n = 0;
    for (int k = 1; k < kBins; ++k) {  // split between bin k-1 and bin k
      acc.extend(bin_box[k - 1]);
      n += count[k - 1];
      if (n == 0 || right_count[k] == 0) continue;
      const double cost = BinaryNode{acc}.area() * n + right_area[k] * right_count[k];
      if (cost < best) {
        best = cost;
        best_k = k;
      }
    }
    return best_k;
  }

  // Puts the median centroid of ids[b, e) along the axis (ties by index) at the middle,
  // smaller ones before it; returns the middle.
  std::size_t median_split(std::vector<int>& ids, std::size_t b, std::size_t e, int axis) const {
    const std::size_t mid = b + (e - b) / 2;
    std::nth_element(ids.begin() + b, ids.begin() + mid, ids.begin() + e, [&](int x, int y) {
      if (centroids_[x][axis] != centroids_[y][axis])
        return centroids_[x][axis] < centroids_[y][axis];
      return x < y;
    });
    return mid;
  }

  const std::vector<Eigen::AlignedBox3d>& boxes_;
  const std::vector<Eigen::Vector3d>& centroids_;
  std::vector<BinaryNode> nodes_;
};

float round_down(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// Collapses the binary tree into 4-wide nodes, assigning triangles their leaf order.
class Collapser {
 public:
  Collapser(const std::vector<BinaryNode>& bin, MeshBvh& out) : bin_(bin), out_(out) {}

  void run() {
    out_.nodes.clear();
    out_.triangles.clear();
    out_.original.clear();
    out_.ranges.clear();
    out_.depth = 0;
    emit(0, 1);
  }

 private:
  // The binary nodes the 4-wide node of binary node b holds: its children, the largest inner
  // ones opened up until there are four (or only leaves); b itself for a one-triangle mesh.
  std::vector<int> children_of(int b) const {
    if (bin_[b].triangle >= 0) return {b};  // the root holds the triangle itself
    std::vector<int> kids = {bin_[b].left, bin_[b].right};
    while (kids.size() < 4) {
      int pick = -1;
      double pick_area = -1.0;
      for (std::size_t k = 0; k < kids.size(); ++k) {
        if (bin_[kids[k]].triangle >= 0) continue;
        const double a = bin_[kids[k]].area();
        if (a > pick_area) {
          pick_area = a;
          pick = static_cast<int>(k);
        }
      }
      if (pick < 0) break;
      const int opened = kids[pick];
      kids[pick] = bin_[opened].left;
      kids.insert(kids.begin() + pick + 1, bin_[opened].right);
    }
    return kids;
  }

  int emit(int b, std::size_t depth) {
    out_.depth = std::max(out_.depth, depth);
    const std::vector<int> kids = children_of(b);
    const int index = static_cast<int>(out_.nodes.size());
    out_.nodes.emplace_back();
    out_.ranges.emplace_back();
    const int first = static_cast<int>(out_.original.size());
    Bvh4Node node;
    node.triangle_mask = 0;
    for (int k = 0; k < 4; ++k) {
      node.child[k] = kEmpty;
      for (int a = 0; a < 3; ++a) {
        node.lo[a][k] = std::numeric_limits<float>::infinity();
        node.hi[a][k] = -std::numeric_limits<float>::infinity();
      }
    }
    for (std::size_t k = 0; k < kids.size(); ++k) {
      const BinaryNode& c = bin_[kids[k]];
      for (int a = 0; a < 3; ++a) {
        node.lo[a][k] = round_down((c.box.min()[a] - out_.origin[a]) * out_.box_scale);
        node.hi[a][k] = round_up((c.box.max()[a] - out_.origin[a]) * out_.box_scale);
      }
      if (c.triangle >= 0) {
        node.triangle_mask |= 1u << k;
        node.child[k] = ~static_cast<std::int32_t>(out_.original.size());
        out_.original.push_back(c.triangle);
      } else {
        node.child[k] = emit(kids[k], depth + 1);
      }
    }
    out_.nodes[index] = node;
    // Emission is depth-first, so a subtree's triangles are contiguous in leaf order.
    out_.ranges[index] = {first, static_cast<int>(out_.original.size())};
    return index;
  }

  const std::vector<BinaryNode>& bin_;
  MeshBvh& out_;
};

}  // namespace

// Memory. The hierarchy keeps about 340 bytes per triangle (the prepared triangles and
// planes, 144; the expansions, about 90; the nodes, about 43; the mesh, 24; the orders).
// The build's temporaries (boxes and centroids, 72 bytes per triangle; the binary tree,
// 128) are freed as soon as the next stage no longer needs them, so that the build's
// peak stays below what the finished hierarchy holds.
void MeshBvh::check(const TriangleMesh& m, const MeshQueryOptions& options) {
  if (m.triangles.empty()) throw std::invalid_argument("MeshQuery: the mesh has no triangles");
  if (!(options.winding_beta > 1.0) || !std::isfinite(options.winding_beta))
    throw std::invalid_argument("MeshQuery: winding_beta must be finite and > 1");
  const auto nv = static_cast<long long>(m.vertices.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int k : m.triangles[t])
      if (k < 0 || k >= nv)
        throw std::invalid_argument("MeshQuery: triangle " + std::to_string(t) +
                                    " has a vertex index out of range");
  for (const auto& v : m.vertices)
    if (!v.allFinite()) throw std::invalid_argument("MeshQuery: non-finite vertex coordinate");
}

void MeshBvh::build(TriangleMesh m, const MeshQueryOptions& options) {
  check(m, options);
  mesh = std::move(m);
  winding_beta = options.winding_beta;
  const Eigen::AlignedBox3d all = mesh.bounds();
  origin = all.center();
  extent = all.sizes().maxCoeff();
  // The power of two 2^-e with extent < 2^e: box coordinates relative to the centre then
  // lie within [-1/2, 1/2], so that single precision neither overflows on huge meshes
  // nor underflows on tiny ones. A subnormal extent (e < -1022) would make 2^-e infinite,
  // and a query's box coordinates 0 * inf, NaN, which every box test passes: the scale
  // stops at 2^1000 (the boxes, rounded outward, then hold their triangles all the same).
  box_scale = 1.0;
  if (extent > 0.0 && std::isfinite(extent)) {
    int e = 0;
    std::frexp(extent, &e);
    box_scale = std::ldexp(1.0, -std::max(e, -1000));
  }
  build_tree();
  prepare_triangles();
  build_expansions();
}

void MeshBvh::build_tree() {
  std::vector<BinaryNode> bin;
  {
    const std::size_t n = mesh.triangles.size();
    std::vector<Eigen::AlignedBox3d> boxes(n);
    std::vector<Eigen::Vector3d> centroids(n);
    for (std::size_t t = 0; t < n; ++t) {
      boxes[t].setEmpty();
      for (int k = 0; k < 3; ++k) boxes[t].extend(mesh.corner(t, k));
      centroids[t] = (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3.0;
    }
    bin = BinaryBuilder(boxes, centroids).build();
  }
  Collapser(bin, *this).run();
  std::vector<BinaryNode>().swap(bin);
  nodes.shrink_to_fit();
  original.shrink_to_fit();
  ranges.shrink_to_fit();
}

void MeshBvh::prepare_triangles() {
  triangles.resize(original.size());
  planes.resize(original.size());
  for (std::size_t i = 0; i < original.size(); ++i) {
    const int t = original[i];
    const Eigen::Vector3d &a = mesh.corner(t, 0), &b = mesh.corner(t, 1), &c = mesh.corner(t, 2);
    const PreparedTriangle prepared = prepare_triangle(a, b, c);
    triangles[i] = prepared.triangle;
    planes[i] = prepared.plane;
  }
}

// Far-field expansions. Each node's moments are summed over its own triangles, relative
// to its own centre, so no moment is shifted and nothing cancels; the cost is one pass
// over the triangles per tree level. The ranges are needed here only, and freed after.
void MeshBvh::build_expansions() {
  expansions.assign(nodes.size(), WindingExpansion{});
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const auto [first, last] = ranges[i];
    WindingExpansion& e = expansions[i];
    double area = 0.0;
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero(), plain = Eigen::Vector3d::Zero();
    for (int t = first; t < last; ++t) {
      const QueryTriangle& q = triangles[static_cast<std::size_t>(t)];
      const Eigen::Vector3d c = q.a + (q.ab + q.ac) / 3.0;
      const double a = 0.5 * q.ab.cross(q.ac).norm();
      area += a;
      weighted += a * c;
      plain += c;
    }
    // Only zero-area triangles below: any centre will do, take their mean centroid.
    e.centre =
        area > 0.0 ? Eigen::Vector3d(weighted / area) : Eigen::Vector3d(plain / (last - first));
    Eigen::Matrix3d second[3] = {Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero(),
                                 Eigen::Matrix3d::Zero()};
    for (int t = first; t < last; ++t) {
      const QueryTriangle& q = triangles[static_cast<std::size_t>(t)];
      const Eigen::Vector3d v[3] = {q.a - e.centre, q.a + q.ab - e.centre, q.a + q.ac - e.centre};
      const Eigen::Vector3d vector_area = 0.5 * q.ab.cross(q.ac);
      const Eigen::Vector3d sum = v[0] + v[1] + v[2];
      // Mean of d and of d d^T over the triangle: the centroid, and
      // (sum_k v_k v_k^T + s s^T) / 12 with s = v_0 + v_1 + v_2.
      const Eigen::Vector3d mean = sum / 3.0;
      const Eigen::Matrix3d mean_outer = (v[0] * v[0].transpose() + v[1] * v[1].transpose() +
                                          v[2] * v[2].transpose() + sum * sum.transpose()) /
                                         12.0;
      e.normal_sum += vector_area;
      e.first_moment += mean * vector_area.transpose();
      for (int k = 0; k < 3; ++k) second[k] += vector_area[k] * mean_outer;
      for (const Eigen::Vector3d& d : v) e.radius = std::max(e.radius, d.norm());
    }
    for (int k = 0; k < 3; ++k) e.second_moment[k] = SymmetricMatrix3(second[k]);
  }
  std::vector<std::pair<int, int>>().swap(ranges);
}

namespace {

struct StackEntry {
  std::int32_t node;
  float d2;
};

// Squared distances from the query to the four child boxes of a node (float), and the
// 4-bit mask of the children whose distance is <= threshold. Empty slots have inverted
// boxes, hence infinite distance, and never pass: the threshold is at most FLT_MAX.
inline unsigned child_box_distances(const Bvh4Node& n, const float q[3], float threshold,
                                    float out[4]) {
#if defined(__SSE2__)
  const __m128 zero = _mm_setzero_ps();
  __m128 acc = zero;
  for (int a = 0; a < 3; ++a) {
    const __m128 qa = _mm_set1_ps(q[a]);
    const __m128 below = _mm_sub_ps(_mm_load_ps(n.lo[a]), qa);
    const __m128 above = _mm_sub_ps(qa, _mm_load_ps(n.hi[a]));
    const __m128 d = _mm_max_ps(_mm_max_ps(below, above), zero);
    acc = _mm_add_ps(acc, _mm_mul_ps(d, d));
  }
  _mm_storeu_ps(out, acc);
  return static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(acc, _mm_set1_ps(threshold))));
#else
  unsigned mask = 0;
  for (int k = 0; k < 4; ++k) {
    float s = 0.0f;
    for (int a = 0; a < 3; ++a) {
      const float d = std::max(std::max(n.lo[a][k] - q[a], q[a] - n.hi[a][k]), 0.0f);
      s += d * d;
    }
    out[k] = s;
    if (s <= threshold) mask |= 1u << k;
  }
  return mask;
#endif
}

inline int lowest_bit(unsigned mask) {
  return __builtin_ctz(mask);
}

// Pruning threshold for the float box distances (in box units), given the best squared
// distance so far (in mesh units). A box is skipped only when its computed distance
// exceeds the best distance plus `slack`, which bounds the float error of the box test
// (see closest()).
inline float prune_threshold(double best2, double box_scale, double slack) {
  constexpr float kMax = std::numeric_limits<float>::max();
  const double t = std::sqrt(best2) * box_scale + slack;
  const double t2 = t * t * (1.0 + 0x1p-20);
  if (!(t2 < static_cast<double>(kMax))) return kMax;
  return std::min(round_up(t2), kMax);
}

// Queries with |p - origin|_max + extent beyond this take closest_far(). Below it every
// length is below 2^201, so no product of up to four lengths can overflow a double
// (the region tests of closest_on_triangle multiply two dot products; squared
// distances and the plane bound multiply two lengths).
constexpr double kNearReach = 0x1p200;

// The query's box coordinates are clamped to [-kBoxClamp, kBoxClamp]. Every box lies
// within [-1, 1], so clamping only moves the query towards every box along each axis
// it is outside of: box distances can only shrink, and pruning stays conservative.
// Each per-axis distance is then below 2^61, and the sum of three squares below 2^124,
// which float holds, while empty slots (inverted infinite boxes) stay at infinity.
constexpr double kBoxClamp = 0x1p60;

// Closest point by brute force, in coordinates scaled by a power of two 2^-e with
// max(|p|, |vertices|) < 2^e, so that nothing overflows however far p is: every scaled
// length is below 4. Scaling by a power of two is exact short of underflow, so this is
// the arithmetic of the near path. Underflow only loses what is tiny next to |p| or
// the mesh's coordinates, with one exception: a triangle whose scaled edges are below
// 2^-250 (whose products of four lengths would underflow and upset the region tests)
// is queried as its edges, off by at most its size, far below the rounding of the
// scaled coordinates. Ties go to the first triangle in BVH order.
ClosestPoint closest_far(const MeshBvh& bvh, const Eigen::Vector3d& p, QueryCounters* counters,
                         double* distance) {
  if (!p.allFinite())
    throw std::invalid_argument("MeshQuery::closest_point: the query point is not finite");
  // Vertices lie within extent / 2 of the origin, per coordinate.
  const double reach =
      std::max(p.cwiseAbs().maxCoeff(), bvh.origin.cwiseAbs().maxCoeff() + bvh.extent);
  int e = 0;
  std::frexp(std::min(reach, std::numeric_limits<double>::max()), &e);
  const double s = std::ldexp(1.0, -e);
  const Eigen::Vector3d ps = p * s;
  ClosestPoint best;
  double best_s2 = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_cs = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < bvh.triangles.size(); ++i) {
    QueryTriangle t = bvh.triangles[i];
    t.a *= s;
    t.ab *= s;
    t.ac *= s;
    t.ab_ab = t.ab.dot(t.ab);
    t.ab_ac = t.ab.dot(t.ac);
    t.ac_ac = t.ac.dot(t.ac);
    if (std::max({t.ab_ab, t.ac_ac, (t.ac - t.ab).squaredNorm()}) < 0x1p-500)
      t.shape = TriangleShape::kDegenerate;
    const Eigen::Vector3d cs = closest_on_triangle(ps, t, bvh.planes[i].normal);
    const double d2 = (ps - cs).squaredNorm();
    if (d2 < best_s2 || best.triangle < 0) {
      best_s2 = d2;
      best_cs = cs;
      best.triangle = static_cast<int>(i);
    }
  }
  if (counters != nullptr) counters->triangles_tested += bvh.triangles.size();
  for (int k = 0; k < 3; ++k) best.point[k] = std::ldexp(best_cs[k], e);
  best.squared_distance = std::ldexp(best_s2, 2 * e);
  best.triangle = bvh.original[static_cast<std::size_t>(best.triangle)];
  *distance = std::ldexp(std::sqrt(best_s2), e);
  return best;
}

}  // namespace

ClosestPoint closest(const MeshBvh& bvh, const Eigen::Vector3d& p, int hint_order,
                     QueryCounters* counters, double* distance) {
  const Eigen::Vector3d pl = p - bvh.origin;
  const double reach = pl.cwiseAbs().maxCoeff() + bvh.extent;
  if (!(reach <= kNearReach)) return closest_far(bvh, p, counters, distance);  // or not finite
  const Eigen::Vector3d ql =
      (pl * bvh.box_scale).cwiseMax(-kBoxClamp).cwiseMin(kBoxClamp);  // box units
  const float q[3] = {static_cast<float>(ql.x()), static_cast<float>(ql.y()),
                      static_cast<float>(ql.z())};
  // Float error of a box distance: rounding q to float (half an ulp of |q|), the
  // subtractions and the sum of squares (a few ulps of the operands, which are bounded
  // by |q| + the scaled extent). 8 ulps of that magnitude covers them with room to spare.
  const double slack = 8.0 * 0x1p-24 * (ql.cwiseAbs().maxCoeff() + bvh.extent * bvh.box_scale);
  // Rounding of n.p - n.a: a few ulps of |p| and |a| (bounded by |origin| + extent).
  const double plane_slack =
      16.0 * 0x1p-53 * (p.cwiseAbs().sum() + bvh.origin.cwiseAbs().sum() + 2.0 * bvh.extent);

  ClosestPoint best;
  best.squared_distance = std::numeric_limits<double>::infinity();
  std::uint64_t visited = 0, tested = 0;
  auto test_triangle = [&](int order) {
    // The distance to the triangle's plane bounds the distance to the triangle from
    // below (see TrianglePlane); plane_slack covers the rounding of n.p and of the
    // stored n.a.
    const TrianglePlane& bound = bvh.planes[static_cast<std::size_t>(order)];
    const double plane = std::abs(bound.normal.dot(p) - bound.offset) - bound.error - plane_slack;
    if (plane > 0.0 && plane * plane >= best.squared_distance) return false;
    ++tested;
    const Eigen::Vector3d c =
        closest_on_triangle(p, bvh.triangles[static_cast<std::size_t>(order)], bound.normal);
    const double d2 = (p - c).squaredNorm();
    if (d2 < best.squared_distance) {
      best.squared_distance = d2;
      best.point = c;
      best.triangle = order;
      return true;
    }
    return false;
  };
  if (hint_order >= 0) test_triangle(hint_order);
  float threshold = prune_threshold(best.squared_distance, bvh.box_scale, slack);

  // Depth-first, nearest child first: the traversal descends into the nearest
  // surviving child directly and stacks the others, farthest deepest.
  StackEntry stack[512];
  int sp = 0;
  std::int32_t current = 0;
  for (;;) {
    const Bvh4Node& node = bvh.nodes[static_cast<std::size_t>(current)];
    ++visited;
    float d2[4];
    unsigned hits = child_box_distances(node, q, threshold, d2);
    // Triangles first: they may lower the threshold before inner nodes are stacked.
    const unsigned triangles = hits & node.triangle_mask;
    hits &= ~node.triangle_mask;
    for (unsigned m = triangles; m != 0; m &= m - 1) {
      const int k = lowest_bit(m);
      if (d2[k] <= threshold && test_triangle(~node.child[k]))
        threshold = prune_threshold(best.squared_distance, bvh.box_scale, slack);
    }
    // Surviving inner nodes, in ascending distance.
    StackEntry cand[4];
    int nc = 0;
    for (unsigned m = hits; m != 0; m &= m - 1) {
      const int k = lowest_bit(m);
      if (d2[k] > threshold) continue;
      int j = nc++;
      while (j > 0 && cand[j - 1].d2 > d2[k]) {
        cand[j] = cand[j - 1];
        --j;
      }
      cand[j] = {node.child[k], d2[k]};
    }
    if (nc > 0) {
      for (int k = nc - 1; k > 0; --k) stack[sp++] = cand[k];
      current = cand[0].node;
      continue;
    }
    // Nothing here: resume from the stack, skipping entries the threshold now prunes.
    while (sp > 0 && stack[sp - 1].d2 > threshold) --sp;
    if (sp == 0) break;
    current = stack[--sp].node;
  }
  if (counters != nullptr) {
    counters->nodes_visited += visited;
    counters->triangles_tested += tested;
  }
  // Every box distance is finite (kBoxClamp) and every squared distance too
  // (kNearReach), so the first triangle reached is always taken. Never index with -1.
  if (best.triangle < 0) return closest_far(bvh, p, counters, distance);
  best.triangle = bvh.original[static_cast<std::size_t>(best.triangle)];
  *distance = std::sqrt(best.squared_distance);
  return best;
}

}  // namespace detail

struct detail::ClosestPointAccess {
  static ClosestPoint query(const MeshBvh& bvh, const Eigen::Vector3d& p, int hint_order,
                            QueryCounters* counters) {
    double distance = 0.0;
    ClosestPoint c = closest(bvh, p, hint_order, counters, &distance);
    c.distance_ = distance;
    return c;
  }
};

double ClosestPoint::distance() const {
  return distance_;
}

namespace {

std::vector<int> inverse_order(const detail::MeshBvh& bvh) {
  std::vector<int> order_of(bvh.mesh.triangles.size(), -1);
  for (std::size_t i = 0; i < bvh.original.size(); ++i)
    order_of[static_cast<std::size_t>(bvh.original[i])] = static_cast<int>(i);
  return order_of;
}

// A fan from the centroid of each chain's vertices (see MeshQueryOptions::cap_holes).
TriangleMesh hole_caps(const TriangleMesh& mesh) {
  TriangleMesh caps;
  for (const std::vector<int>& loop : boundary_loops(mesh)) {
    if (loop.size() < 3) continue;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int v : loop) centre += mesh.vertices[static_cast<std::size_t>(v)];
    centre /= static_cast<double>(loop.size());
    if (!centre.allFinite()) {  // the sum overflowed (coordinates near +-DBL_MAX)
      centre.setZero();
      for (int v : loop)
        centre += mesh.vertices[static_cast<std::size_t>(v)] / static_cast<double>(loop.size());
    }
    const int base = static_cast<int>(caps.vertices.size());
    for (int v : loop) caps.vertices.push_back(mesh.vertices[static_cast<std::size_t>(v)]);
    caps.vertices.push_back(centre);
    const int n = static_cast<int>(loop.size());
    for (int k = 0; k < n; ++k) caps.triangles.push_back({base + (k + 1) % n, base + k, base + n});
  }
  return caps;
}

}  // namespace

MeshQuery::MeshQuery(const TriangleMesh& mesh, const MeshQueryOptions& options)
    : MeshQuery(TriangleMesh(mesh), options) {}

// The caps are found (an edge table of the mesh, about 60 bytes per triangle) before the
// hierarchy is built, so that the two never take memory at the same time.
MeshQuery::MeshQuery(TriangleMesh&& mesh, const MeshQueryOptions& options)
    : impl_(std::make_unique<Impl>()) {
  TriangleMesh caps;
  detail::MeshBvh::check(mesh, options);
  if (options.cap_holes) caps = hole_caps(mesh);
  impl_->bvh.build(std::move(mesh), options);
  impl_->order_of = inverse_order(impl_->bvh);
  if (!caps.triangles.empty()) {
    impl_->caps = std::make_unique<detail::MeshBvh>();
    impl_->caps->build(std::move(caps), options);
    impl_->caps_order_of = inverse_order(*impl_->caps);
  }
}

MeshQuery::~MeshQuery() = default;
MeshQuery::MeshQuery(MeshQuery&&) noexcept = default;
MeshQuery& MeshQuery::operator=(MeshQuery&&) noexcept = default;

ClosestPoint MeshQuery::closest_point(const Eigen::Vector3d& p, QueryCounters* counters) const {
  ClosestPoint best = detail::ClosestPointAccess::query(impl_->bvh, p, -1, counters);
  if (impl_->caps) {
    ClosestPoint cap = detail::ClosestPointAccess::query(*impl_->caps, p, -1, counters);
    if (cap.distance() < best.distance()) {
      cap.triangle += static_cast<int>(impl_->order_of.size());
      best = cap;
    }
  }
  return best;
}

ClosestPoint MeshQuery::closest_point(const Eigen::Vector3d& p, int hint_triangle,
                                      QueryCounters* counters) const {
  const std::size_t n = impl_->order_of.size();
  if (hint_triangle < 0 ||
      static_cast<std::size_t>(hint_triangle) >= n + impl_->caps_order_of.size())
    throw std::invalid_argument("MeshQuery::closest_point: hint triangle out of range");
  const auto hint = static_cast<std::size_t>(hint_triangle);
  ClosestPoint best = detail::ClosestPointAccess::query(
      impl_->bvh, p, hint < n ? impl_->order_of[hint] : -1, counters);
  if (impl_->caps) {
    ClosestPoint cap = detail::ClosestPointAccess::query(
        *impl_->caps, p, hint < n ? -1 : impl_->caps_order_of[hint - n], counters);
    if (cap.distance() < best.distance()) {
      cap.triangle += static_cast<int>(n);
      best = cap;
    }
  }
  return best;
}

namespace {

// f applied to every point, result i from point i, on `threads` threads (threads.h: 0 for
// all cores, at most kMaxThreads). Each result depends on its point alone, so the output
// is the same for any thread count.
template <typename T, typename F>
std::vector<T> map_points(const std::vector<Eigen::Vector3d>& points, int threads, F f) {
  const int nt = thread_count(threads);
  std::vector<T> out(points.size());
  const long long n = static_cast<long long>(points.size());
#pragma omp parallel for schedule(dynamic, 256) num_threads(nt)
  for (long long i = 0; i < n; ++i) out[i] = f(points[i]);
  return out;
}

}  // namespace

std::vector<ClosestPoint> MeshQuery::closest_points(const std::vector<Eigen::Vector3d>& points,
                                                    int threads) const {
  // Checked here: an exception must not escape the parallel loop.
  for (const Eigen::Vector3d& p : points)
    if (!p.allFinite())
      throw std::invalid_argument("MeshQuery::closest_points: a query point is not finite");
  return map_points<ClosestPoint>(points, threads,
                                  [this](const Eigen::Vector3d& p) { return closest_point(p); });
}

std::vector<double> MeshQuery::winding_numbers(const std::vector<Eigen::Vector3d>& points,
                                               int threads) const {
  return map_points<double>(points, threads,
                            [this](const Eigen::Vector3d& p) { return winding_number(p); });
}

const TriangleMesh& MeshQuery::mesh() const {
  return impl_->bvh.mesh;
}

const TriangleMesh& MeshQuery::cap_mesh() const {
  return impl_->caps ? impl_->caps->mesh : impl_->no_caps;
}

std::array<Eigen::Vector3d, 3> MeshQuery::triangle_corners(int t) const {
  const std::size_t n = impl_->order_of.size();
  const TriangleMesh& caps = cap_mesh();
  if (t < 0 || static_cast<std::size_t>(t) >= n + caps.triangles.size())
    throw std::out_of_range("MeshQuery::triangle_corners: no triangle " + std::to_string(t));
  const auto i = static_cast<std::size_t>(t);
  const TriangleMesh& m = i < n ? impl_->bvh.mesh : caps;
  const std::size_t k = i < n ? i : i - n;
  return {m.corner(k, 0), m.corner(k, 1), m.corner(k, 2)};
}

MeshBvhStats MeshQuery::stats() const {
  const detail::MeshBvh& b = impl_->bvh;
  MeshBvhStats s;
  s.triangles = b.triangles.size();
  s.cap_triangles = impl_->caps ? impl_->caps->triangles.size() : 0;
  s.nodes = b.nodes.size();
  s.depth = b.depth;
  const auto bytes = [](const detail::MeshBvh& h, const std::vector<int>& order_of) {
    return h.nodes.capacity() * sizeof(detail::Bvh4Node) +
           h.expansions.capacity() * sizeof(detail::WindingExpansion) +
           h.triangles.capacity() * sizeof(detail::QueryTriangle) +
           h.planes.capacity() * sizeof(detail::TrianglePlane) +
           h.original.capacity() * sizeof(int) + order_of.capacity() * sizeof(int) +
           h.mesh.vertices.capacity() * sizeof(Eigen::Vector3d) +
           h.mesh.triangles.capacity() * sizeof(std::array<int, 3>);
  };
  s.bytes = bytes(b, impl_->order_of);
  if (impl_->caps) s.bytes += bytes(*impl_->caps, impl_->caps_order_of);
  return s;
}

}  // namespace medspheres
