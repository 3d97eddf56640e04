#include "medspheres/triangle_tree.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "bvh_build.h"

namespace medspheres {
namespace {

Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0.0)) return a;
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + ab * t;
}

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Voronoi regions of the vertices, then of the edges, then the face.
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double denom = d1 - d3;
    if (denom > 0.0) return a + ab * (d1 / denom);
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double denom = d2 - d6;
    if (denom > 0.0) return a + ac * (d2 / denom);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double denom = (d4 - d3) + (d5 - d6);
    if (denom > 0.0) return b + (c - b) * ((d4 - d3) / denom);
  }
  const double sum = va + vb + vc;
  if (sum > 0.0 && va >= 0.0 && vb >= 0.0 && vc >= 0.0) {
    const Eigen::Vector3d q = a + ab * (vb / sum) + ac * (vc / sum);
    if (q.allFinite()) return q;
  }
  // Degenerate triangle (or rounding at a region boundary): the nearest edge point.
  const Eigen::Vector3d q0 = closest_point_on_segment(p, a, b);
  const Eigen::Vector3d q1 = closest_point_on_segment(p, b, c);
  const Eigen::Vector3d q2 = closest_point_on_segment(p, c, a);
  const double e0 = (p - q0).squaredNorm(), e1 = (p - q1).squaredNorm(),
               e2 = (p - q2).squaredNorm();
  if (e0 <= e1 && e0 <= e2) return q0;
  return e1 <= e2 ? q1 : q2;
}

BallProximity ball_triangle_proximity(const Eigen::Vector3d& center, double radius,
                                      const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const Eigen::Vector3d& c) {
  const Eigen::Vector3d q = closest_point_on_triangle(center, a, b, c);
  const Eigen::Vector3d diff = q - center;
  const double len = diff.norm();
  BallProximity out;
  out.distance = len - radius;
  if (len > 0.0) {
    out.normal = diff / len;
  } else {
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double area2 = n.norm();
    out.normal = area2 > 0.0 ? Eigen::Vector3d(-n / area2) : Eigen::Vector3d::UnitX();
  }
  return out;
}

TriangleTree::TriangleTree(const TriangleMesh& mesh)
    : vertices_(mesh.vertices), triangles_(mesh.triangles) {
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (!vertices_[i].allFinite())
      throw std::invalid_argument("TriangleTree: vertex " + std::to_string(i) +
                                  " has a non-finite coordinate");
  }
  const int nv = static_cast<int>(vertices_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    for (int k : triangles_[t]) {
      if (k < 0 || k >= nv)
        throw std::invalid_argument("TriangleTree: triangle " + std::to_string(t) +
                                    " has vertex index " + std::to_string(k) + " out of range");
    }
  }
  detail::BuildInput input;
  const std::size_t n = triangles_.size();
  input.split_points.reserve(n);
  input.ball_begin.reserve(n + 1);
  input.balls.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t) {
    input.ball_begin.push_back(static_cast<int>(input.balls.size()));
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k : triangles_[t]) {
      const Eigen::Vector3d& v = vertices_[static_cast<std::size_t>(k)];
      input.balls.push_back({v, 0.0});
      centroid += v;
    }
    input.split_points.push_back(centroid / 3.0);
  }
  input.ball_begin.push_back(static_cast<int>(input.balls.size()));
  const std::vector<detail::BuildNode> built = detail::build_hierarchy(input, 1, order_);
  nodes_.reserve(built.size());
  for (const detail::BuildNode& b : built) {
    Node node;
    node.bounds = detail::fit_rss(b.axes, detail::balls_below(input, order_, b.begin, b.end));
    node.begin = b.begin;
    node.end = b.end;
    node.first_child = b.first_child;
    nodes_.push_back(node);
  }
}

Rss TriangleTree::node_bounds(std::size_t node) const {
  if (node >= nodes_.size())
    throw std::out_of_range("TriangleTree: node " + std::to_string(node) + " does not exist");
  return nodes_[node].bounds;
}

std::vector<std::size_t> TriangleTree::triangles_below(std::size_t node) const {
  if (node >= nodes_.size())
    throw std::out_of_range("TriangleTree: node " + std::to_string(node) + " does not exist");
  std::vector<std::size_t> out;
  for (int k = nodes_[node].begin; k < nodes_[node].end; ++k)
    out.push_back(static_cast<std::size_t>(order_[static_cast<std::size_t>(k)]));
  return out;
}

TargetNode TriangleTree::target_node(std::size_t node) const {
  const Node& n = nodes_[node];
  TargetNode out;
  out.handle = static_cast<std::intptr_t>(node);
  out.is_leaf = n.first_child < 0;
  if (out.is_leaf)
    out.primitive = order_[static_cast<std::size_t>(n.begin)];
  else
    out.bounds = n.bounds;
  return out;
}

std::optional<TargetNode> TriangleTree::root() const {
  if (nodes_.empty()) return std::nullopt;
  return target_node(0);
}

int TriangleTree::children(const TargetNode& node, TargetNode* out) const {
  const Node& n = nodes_[static_cast<std::size_t>(node.handle)];
  if (n.first_child < 0) return 0;
  out[0] = target_node(static_cast<std::size_t>(n.first_child));
  out[1] = target_node(static_cast<std::size_t>(n.first_child) + 1);
  return 2;
}

BallProximity TriangleTree::ball_proximity(const TargetNode& leaf, const Eigen::Vector3d& p_BC,
                                           double radius) const {
  const std::array<int, 3>& t = triangles_[static_cast<std::size_t>(leaf.primitive)];
  return ball_triangle_proximity(p_BC, radius, vertices_[static_cast<std::size_t>(t[0])],
                                 vertices_[static_cast<std::size_t>(t[1])],
                                 vertices_[static_cast<std::size_t>(t[2])]);
}

}  // namespace medspheres
