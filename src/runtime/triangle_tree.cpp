#include "medspheres/triangle_tree.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "bvh_build.h"

namespace medspheres {
namespace {

// The ball's answer given q, the triangle's point nearest to its centre.
BallProximity ball_answer(const Eigen::Vector3d& center, double radius, const Eigen::Vector3d& q,
                          const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c) {
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

void check_mesh(const TriangleMesh& mesh) {
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite())
      throw std::invalid_argument("TriangleTree: vertex " + std::to_string(i) +
                                  " has a non-finite coordinate");
  }
  const int nv = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k : mesh.triangles[t]) {
      if (k < 0 || k >= nv)
        throw std::invalid_argument("TriangleTree: triangle " + std::to_string(t) +
                                    " has vertex index " + std::to_string(k) + " out of range");
    }
  }
}

}  // namespace

BallProximity ball_triangle_proximity(const Eigen::Vector3d& center, double radius,
                                      const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const Eigen::Vector3d& c) {
  return ball_answer(center, radius, closest_point_on_triangle(center, a, b, c), a, b, c);
}

TriangleTree::TriangleTree(const TriangleMesh& mesh)
    : vertices_(mesh.vertices), triangles_(mesh.triangles) {
  check_mesh(mesh);
  prepared_.reserve(triangles_.size());
  normals_.reserve(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const detail::PreparedTriangle p =
        detail::prepare_triangle(mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2));
    prepared_.push_back(p.triangle);
    normals_.push_back(p.plane.normal);
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
  const auto t = static_cast<std::size_t>(leaf.primitive);
  const Eigen::Vector3d q = detail::closest_on_triangle(p_BC, prepared_[t], normals_[t]);
  const std::array<int, 3>& c = triangles_[t];
  return ball_answer(p_BC, radius, q, vertices_[static_cast<std::size_t>(c[0])],
                     vertices_[static_cast<std::size_t>(c[1])],
                     vertices_[static_cast<std::size_t>(c[2])]);
}

}  // namespace medspheres
