#pragma once
// The flat arrays of a SphereTree, shared by its construction (sphere_tree.cpp) and its
// queries (sphere_tree_query.cpp). Private to the runtime target.

#include <cstddef>
#include <cstdint>
#include <memory>

#include "medspheres/sphere_tree.h"

namespace medspheres {
namespace detail {

/// A sphere in tree order, in frame A.
struct PackedSphere {
  double c[3];
  double r;
};

/// An RSS node. Beside the RSS it keeps the minimum enclosing ball of its spheres, a
/// cheaper first test; the rectangle's centre is stored as an offset from the ball's
/// centre. Leaves hold spheres [first, first + count); internal nodes have count == 0
/// and the children first and first + 1.
struct alignas(16) RssNode {
  double c[3];     ///< centre of the minimum enclosing ball
  double ball_r;   ///< its radius
  double o[3];     ///< centre of the rectangle minus c
  double u[3];     ///< x_T, the longer side's direction
  double v[3];     ///< y_T
  double half[2];  ///< half side lengths along u and v
  double r;        ///< swept radius
  double max_r;    ///< largest sphere radius below the node
  std::int32_t first;
  std::int32_t count;
};

/// A ball node; same child and sphere conventions as RssNode.
struct alignas(16) BallNode {
  double c[3];
  double r;
  double max_r;
  std::int32_t first;
  std::int32_t count;
};

struct FreeAligned {
  void operator()(unsigned char* p) const noexcept;
};

}  // namespace detail

/// One allocation holds the nodes (RssNode or BallNode), the spheres in tree order, their
/// original indices and the inverse permutation; the pointers below point into it.
struct SphereTree::Layout {
  BoundingVolumeKind kind = BoundingVolumeKind::rss;
  std::size_t num_spheres = 0;
  std::size_t num_nodes = 0;
  std::size_t block_bytes = 0;
  std::unique_ptr<unsigned char[], detail::FreeAligned> block;
  const detail::RssNode* rss_nodes = nullptr;    ///< kind rss
  const detail::BallNode* ball_nodes = nullptr;  ///< kind ball
  const detail::PackedSphere* spheres = nullptr;
  const std::int32_t* original_index = nullptr;  ///< tree position -> index in the set
  const std::int32_t* tree_position = nullptr;   ///< index in the set -> tree position
  SphereTreeStats stats;
};

/// The layout of a tree, or nullptr for an empty tree.
const SphereTree::Layout* tree_layout(const SphereTree& tree) noexcept;

}  // namespace medspheres
