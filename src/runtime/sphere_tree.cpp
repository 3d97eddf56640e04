#include "medspheres/sphere_tree.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <stdexcept>
#include <string>

#include "bvh_build.h"
#include "medspheres/min_enclosing_ball.h"
#include "traversal/sphere_tree_layout.h"

namespace medspheres {
namespace detail {

void FreeAligned::operator()(unsigned char* p) const noexcept {
  ::operator delete[](p, std::align_val_t(64));
}

}  // namespace detail

namespace {

constexpr std::size_t kAlign = 64;

std::size_t round_up(std::size_t n) {
  return (n + kAlign - 1) / kAlign * kAlign;
}

const SphereTree::Layout& checked_layout(const SphereTree::Layout* layout, std::size_t node) {
  if (layout == nullptr || node >= layout->num_nodes)
    throw std::out_of_range("SphereTree: node " + std::to_string(node) + " does not exist");
  return *layout;
}

// Children / sphere range of a node, whatever its kind.
void node_links(const SphereTree::Layout& l, std::size_t node, std::int32_t& first,
                std::int32_t& count) {
  if (l.kind == BoundingVolumeKind::rss) {
    first = l.rss_nodes[node].first;
    count = l.rss_nodes[node].count;
  } else {
    first = l.ball_nodes[node].first;
    count = l.ball_nodes[node].count;
  }
}

// Writes node k of the block at \p base: its bounding volume over \p balls (the spheres
// below it), the largest radius below and its links.
void write_node(BoundingVolumeKind kind, const Eigen::Matrix3d& axes,
                const std::vector<detail::Ball>& balls, double max_r, std::int32_t first,
                std::int32_t count, unsigned char* base, std::size_t k) {
  const detail::Ball ball = min_enclosing_ball(balls);
  if (kind == BoundingVolumeKind::rss) {
    const Rss rss = detail::fit_rss(axes, balls);
    const Eigen::Vector3d offset = rss.center() - ball.center;
    detail::RssNode node{};
    for (int i = 0; i < 3; ++i) {
      node.c[i] = ball.center[i];
      node.o[i] = offset[i];
      node.u[i] = rss.axis(i, 0);
      node.v[i] = rss.axis(i, 1);
    }
    node.ball_r = ball.radius;
    node.half[0] = 0.5 * rss.length[0];
    node.half[1] = 0.5 * rss.length[1];
    node.r = rss.radius;
    node.max_r = max_r;
    node.first = first;
    node.count = count;
    new (reinterpret_cast<detail::RssNode*>(base) + k) detail::RssNode(node);
  } else {
    detail::BallNode node{};
    for (int i = 0; i < 3; ++i) node.c[i] = ball.center[i];
    node.r = ball.radius;
    node.max_r = max_r;
    node.first = first;
    node.count = count;
    new (reinterpret_cast<detail::BallNode*>(base) + k) detail::BallNode(node);
  }
}

// The hierarchy builder's input: every sphere a split point and a ball of its own.
detail::BuildInput build_input(const SphereSet& set) {
  const std::size_t n = set.spheres.size();
  detail::BuildInput input;
  input.split_points.reserve(n);
  input.ball_begin.reserve(n + 1);
  input.balls.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    input.split_points.push_back(set.spheres[i].center);
    input.ball_begin.push_back(static_cast<int>(i));
    input.balls.push_back({set.spheres[i].center, set.spheres[i].radius});
  }
  input.ball_begin.push_back(static_cast<int>(n));
  return input;
}

// The layout's one allocation: nodes, then spheres, then original indices and their
// inverse, each part aligned; the spheres and indices written in tree order.
void allocate_and_fill(SphereTree::Layout& layout, const SphereSet& set,
                       const std::vector<int>& order) {
  const std::size_t n = layout.num_spheres, num_nodes = layout.num_nodes;
  const std::size_t node_bytes = layout.kind == BoundingVolumeKind::rss
                                     ? sizeof(detail::RssNode) * num_nodes
                                     : sizeof(detail::BallNode) * num_nodes;
  const std::size_t sphere_offset = round_up(node_bytes);
  const std::size_t index_offset = sphere_offset + round_up(sizeof(detail::PackedSphere) * n);
  const std::size_t position_offset = index_offset + round_up(sizeof(std::int32_t) * n);
  const std::size_t total = position_offset + round_up(sizeof(std::int32_t) * n);
  layout.block_bytes = total;
  if (total > 0)
    layout.block.reset(
        static_cast<unsigned char*>(::operator new[](total, std::align_val_t(kAlign))));
  unsigned char* base = layout.block.get();
  auto* spheres = reinterpret_cast<detail::PackedSphere*>(base + sphere_offset);
  auto* original = reinterpret_cast<std::int32_t*>(base + index_offset);
  auto* position = reinterpret_cast<std::int32_t*>(base + position_offset);
  for (std::size_t i = 0; i < n; ++i) {
    const Sphere& s = set.spheres[static_cast<std::size_t>(order[i])];
    new (spheres + i) detail::PackedSphere{{s.center.x(), s.center.y(), s.center.z()}, s.radius};
    new (original + i) std::int32_t(order[i]);
  }
  for (std::size_t i = 0; i < n; ++i)
    new (position + order[i]) std::int32_t(static_cast<std::int32_t>(i));
  layout.spheres = spheres;
  layout.original_index = original;
  layout.tree_position = position;
}

// Every node of the built hierarchy written into the layout's block, and the tree's
// statistics.
void write_nodes(SphereTree::Layout& layout, const detail::BuildInput& input,
                 const std::vector<int>& order, const std::vector<detail::BuildNode>& built) {
  unsigned char* base = layout.block.get();
  const std::size_t n = layout.num_spheres;
  SphereTreeStats& stats = layout.stats;
  stats.spheres = n;
  stats.nodes = built.size();
  stats.min_leaf_size = n == 0 ? 0 : n;
  for (std::size_t k = 0; k < built.size(); ++k) {
    const detail::BuildNode& b = built[k];
    const std::vector<detail::Ball> balls = detail::balls_below(input, order, b.begin, b.end);
    double max_r = 0.0;
    for (const detail::Ball& ball : balls) max_r = std::max(max_r, ball.radius);
    const bool leaf = b.first_child < 0;
    const std::int32_t first = leaf ? b.begin : b.first_child;
    const std::int32_t count = leaf ? b.end - b.begin : 0;
    if (leaf) {
      const std::size_t size = static_cast<std::size_t>(b.end - b.begin);
      ++stats.leaves;
      stats.min_leaf_size = std::min(stats.min_leaf_size, size);
      stats.max_leaf_size = std::max(stats.max_leaf_size, size);
    }
    stats.depth = std::max(stats.depth, static_cast<std::size_t>(b.depth));
    write_node(layout.kind, b.axes, balls, max_r, first, count, base, k);
  }
  stats.mean_leaf_size = stats.leaves == 0 ? 0.0 : static_cast<double>(n) / stats.leaves;
  stats.bytes = layout.block_bytes + sizeof(SphereTree) + sizeof(SphereTree::Layout);
  if (layout.kind == BoundingVolumeKind::rss)
    layout.rss_nodes = reinterpret_cast<const detail::RssNode*>(base);
  else
    layout.ball_nodes = reinterpret_cast<const detail::BallNode*>(base);
}

}  // namespace

const SphereTree::Layout* tree_layout(const SphereTree& tree) noexcept {
  return tree.layout_.get();
}

SphereTree::SphereTree() = default;

// Construction (bvh_build.cpp does the work). Top down: at each node a least-squares
// (PCA) fit of the centres below gives three axes, the major one first. The spheres are
// sorted by the projection of their centres on the major axis (ties by index) and the
// first k go to the first child, k the smallest minimiser of k d_1 + (n - k) d_2 (d_i the
// diagonal, in the node's PCA frame, of the box of child i's spheres) among the k that
// leave each child more than a tenth of the n spheres, which bounds the depth by
// log(n) / log(10/9). (The paper cuts at the mean centre; see cheapest_cut.) Every node
// stores the minimum enclosing ball of its spheres, computed by cutting planes: the exact
// ball of a finite set P of points on the spheres (Welzl's move-to-front, Gärtner 1999)
// has radius R_P <= R*; the farthest point of each sphere from its centre joins P until
// the ball of that centre enclosing every sphere, of radius R, has R <= (1 + ball_slack)
// R_P. Enclosure is then made exact: R = max_i |c_i - C| + r_i + 16 eps (|C|_inf + R). An
// RSS node's rectangle lies along the two major axes, its radius and extents fitted as
// in Larsen et al. so that every sphere lies inside: the radius is the largest distance
// from a centre to the rectangle plus that sphere's radius, computed in double, plus
// 16 eps (|corner|_inf + length[0] + length[1] + radius) for its rounding.
SphereTree::SphereTree(const SphereSet& set, const SphereTreeOptions& options) {
  if (options.max_leaf_size < 1)
    throw std::invalid_argument("SphereTreeOptions::max_leaf_size must be >= 1, not " +
                                std::to_string(options.max_leaf_size));
  validate_sphere_set(set, "sphere set", options.allow_points);
  if (set.spheres.size() > static_cast<std::size_t>(INT32_MAX / 2))
    throw std::invalid_argument("SphereTree: too many spheres");

  auto layout = std::make_shared<Layout>();
  layout->kind = options.kind;
  layout->num_spheres = set.spheres.size();
  const detail::BuildInput input = build_input(set);
  std::vector<int> order;
  const std::vector<detail::BuildNode> built =
      detail::build_hierarchy(input, options.max_leaf_size, order);
  layout->num_nodes = built.size();
  allocate_and_fill(*layout, set, order);
  write_nodes(*layout, input, order, built);
  layout_ = std::move(layout);
}

BoundingVolumeKind SphereTree::kind() const noexcept {
  return layout_ ? layout_->kind : BoundingVolumeKind::rss;
}

std::size_t SphereTree::num_spheres() const noexcept {
  return layout_ ? layout_->num_spheres : 0;
}

std::size_t SphereTree::num_nodes() const noexcept {
  return layout_ ? layout_->num_nodes : 0;
}

Sphere SphereTree::sphere(std::size_t i) const {
  if (!layout_ || i >= layout_->num_spheres)
    throw std::out_of_range("SphereTree: sphere " + std::to_string(i) + " does not exist");
  const detail::PackedSphere& p = layout_->spheres[layout_->tree_position[i]];
  return Sphere{Eigen::Vector3d(p.c[0], p.c[1], p.c[2]), p.r};
}

bool SphereTree::is_leaf(std::size_t node) const {
  const Layout& l = checked_layout(layout_.get(), node);
  std::int32_t first = 0, count = 0;
  node_links(l, node, first, count);
  return count > 0;
}

std::size_t SphereTree::left_child(std::size_t node) const {
  const Layout& l = checked_layout(layout_.get(), node);
  std::int32_t first = 0, count = 0;
  node_links(l, node, first, count);
  if (count > 0)
    throw std::invalid_argument("SphereTree: node " + std::to_string(node) + " is a leaf");
  return static_cast<std::size_t>(first);
}

std::size_t SphereTree::right_child(std::size_t node) const {
  return left_child(node) + 1;
}

std::vector<std::size_t> SphereTree::spheres_below(std::size_t node) const {
  const Layout& l = checked_layout(layout_.get(), node);
  // Spheres below a node are contiguous in tree order: find the range via the leftmost
  // and rightmost leaves.
  std::size_t lo = node, hi = node;
  std::int32_t first = 0, count = 0;
  for (node_links(l, lo, first, count); count == 0; node_links(l, lo, first, count))
    lo = static_cast<std::size_t>(first);
  const std::size_t begin = static_cast<std::size_t>(first);
  for (node_links(l, hi, first, count); count == 0; node_links(l, hi, first, count))
    hi = static_cast<std::size_t>(first) + 1;
  const std::size_t end = static_cast<std::size_t>(first + count);
  std::vector<std::size_t> out;
  out.reserve(end - begin);
  for (std::size_t k = begin; k < end; ++k)
    out.push_back(static_cast<std::size_t>(l.original_index[k]));
  return out;
}

Rss SphereTree::rss(std::size_t node) const {
  const Layout& l = checked_layout(layout_.get(), node);
  if (l.kind != BoundingVolumeKind::rss)
    throw std::invalid_argument("SphereTree::rss: the tree's nodes are balls");
  const detail::RssNode& n = l.rss_nodes[node];
  Rss rss;
  const Eigen::Vector3d u(n.u[0], n.u[1], n.u[2]);
  const Eigen::Vector3d v(n.v[0], n.v[1], n.v[2]);
  const Eigen::Vector3d c =
      Eigen::Vector3d(n.c[0], n.c[1], n.c[2]) + Eigen::Vector3d(n.o[0], n.o[1], n.o[2]);
  rss.axis.col(0) = u;
  rss.axis.col(1) = v;
  rss.axis.col(2) = u.cross(v);
  rss.length = Eigen::Vector2d(2.0 * n.half[0], 2.0 * n.half[1]);
  rss.corner = c - u * n.half[0] - v * n.half[1];
  rss.radius = n.r;
  return rss;
}

Sphere SphereTree::bounding_ball(std::size_t node) const {
  const Layout& l = checked_layout(layout_.get(), node);
  if (l.kind == BoundingVolumeKind::rss) {
    const detail::RssNode& n = l.rss_nodes[node];
    return Sphere{Eigen::Vector3d(n.c[0], n.c[1], n.c[2]), n.ball_r};
  }
  const detail::BallNode& n = l.ball_nodes[node];
  return Sphere{Eigen::Vector3d(n.c[0], n.c[1], n.c[2]), n.r};
}

double SphereTree::max_sphere_radius(std::size_t node) const {
  const Layout& l = checked_layout(layout_.get(), node);
  return l.kind == BoundingVolumeKind::rss ? l.rss_nodes[node].max_r : l.ball_nodes[node].max_r;
}

SphereTreeStats SphereTree::stats() const {
  if (!layout_) {
    SphereTreeStats s;
    s.bytes = sizeof(SphereTree);
    return s;
  }
  return layout_->stats;
}

}  // namespace medspheres
