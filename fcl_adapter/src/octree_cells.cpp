// OctreeCells (medspheres/fcl/octree_cells.h): an octree's cells listed once and indexed by
// position; a posed link's mesh against the cells near it, by FCL's mesh-to-box distance.

#include "medspheres/fcl/octree_cells.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fcl/config.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/utility.h>
#include <fcl/narrowphase/distance.h>
#if FCL_HAVE_OCTOMAP
#include <fcl/geometry/octree/octree.h>
#endif

namespace medspheres::fcl {
namespace {

// A group holds at most this many balls of the cover.
constexpr std::size_t kGroupBalls = 8;

// The distance from p to the cube [lo, hi] (0 inside).
double to_cube(const Eigen::Vector3d& p, const ::fcl::AABBd& c) {
  return (p.cwiseMax(c.min_).cwiseMin(c.max_) - p).norm();
}

// The distance between two boxes (0 when they meet).
double between(const ::fcl::AABBd& c, const Eigen::AlignedBox3d& b) {
  const Eigen::Vector3d gap =
      (c.min_ - b.max()).cwiseMax(b.min() - c.max_).cwiseMax(Eigen::Vector3d::Zero());
  return gap.norm();
}

// The cover's balls below `node`, in groups of at most kGroupBalls under a bounding ball.
void group_balls(const SphereTree& tree, std::size_t node, std::vector<Sphere>& bounds,
                 std::vector<std::vector<Sphere>>& groups) {
  const std::vector<std::size_t> below = tree.spheres_below(node);
  if (tree.is_leaf(node) || below.size() <= kGroupBalls) {
    bounds.push_back(tree.bounding_ball(node));
    groups.emplace_back();
    for (std::size_t i : below) groups.back().push_back(tree.sphere(i));
    return;
  }
  group_balls(tree, tree.left_child(node), bounds, groups);
  group_balls(tree, tree.right_child(node), bounds, groups);
}

#if FCL_HAVE_OCTOMAP
// FCL's cells (octree_cells.h): those its distance traversal reaches and tests.
void collect(const ::fcl::OcTree<double>& tree, const ::fcl::OcTree<double>::OcTreeNode* node,
             const ::fcl::AABBd& cube, std::vector<::fcl::AABBd>& out) {
  if (!tree.nodeHasChildren(node)) {
    if (tree.isNodeOccupied(node)) out.push_back(cube);
    return;
  }
  if (!tree.isNodeOccupied(node)) return;
  for (unsigned int i = 0; i < 8; ++i) {
    if (!tree.nodeChildExists(node, i)) continue;
    ::fcl::AABBd child;
    ::fcl::computeChildBV(cube, i, child);
    collect(tree, tree.getNodeChild(node, i), child, out);
  }
}
#endif

}  // namespace

OctreeCells::Link::Link(const BoundedGeometry& g) : mesh_(g.mesh()) {
  if (mesh_ == nullptr)
    throw std::invalid_argument("OctreeCells::Link: the link \"" + g.link() + "\" has no mesh");
  for (int v = 0; v < mesh_->num_vertices; ++v) box_.extend(mesh_->vertices[v]);
  if (box_.isEmpty())
    throw std::invalid_argument("OctreeCells::Link: the link \"" + g.link() + "\" has no vertices");
  if (!g.certified() || g.outer().empty()) return;
  std::vector<Sphere> bounds;
  std::vector<std::vector<Sphere>> groups;
  group_balls(g.outer(), 0, bounds, groups);
  for (std::size_t k = 0; k < bounds.size(); ++k) cover_.push_back({bounds[k], groups[k]});
}

std::size_t OctreeCells::KeyHash::operator()(const Key& k) const {
  const auto h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull ^
                 static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full ^
                 static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull;
  return static_cast<std::size_t>(h ^ (h >> 29));
}

OctreeCells::Key OctreeCells::key_of(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d k = (p / bucket_).array().floor();
  return {static_cast<std::int64_t>(k.x()), static_cast<std::int64_t>(k.y()),
          static_cast<std::int64_t>(k.z())};
}

#if FCL_HAVE_OCTOMAP
OctreeCells::OctreeCells(const ::fcl::OcTree<double>& tree, const Eigen::Isometry3d& X_WO)
    : X_WO_(X_WO) {
  if (!X_WO.matrix().allFinite())
    throw std::invalid_argument("OctreeCells: the octree's pose is not finite");
  if (tree.getRoot() != nullptr) collect(tree, tree.getRoot(), tree.getRootBV(), cells_);
  if (cells_.empty()) return;
  // Buckets four of the smallest cells wide: a link's box spans a few dozen of them.
  double smallest = std::numeric_limits<double>::infinity();
  for (const ::fcl::AABBd& c : cells_) smallest = std::min(smallest, c.width());
  bucket_ = 4.0 * smallest;
  for (std::size_t i = 0; i < cells_.size(); ++i) {
    const Key lo = key_of(cells_[i].min_), hi = key_of(cells_[i].max_);
    for (std::int64_t x = lo.x; x <= hi.x; ++x)
      for (std::int64_t y = lo.y; y <= hi.y; ++y)
        for (std::int64_t z = lo.z; z <= hi.z; ++z)
          buckets_[{x, y, z}].push_back(static_cast<std::uint32_t>(i));
  }
}
#else
OctreeCells::OctreeCells(const ::fcl::OcTree<double>&, const Eigen::Isometry3d&) {
  throw std::invalid_argument("OctreeCells: FCL was built without octomap");
}
#endif

// The cells within `reach` of the mesh's box (in O) and, with a cover, of one of its balls.
void OctreeCells::candidates(const Link& link, const Eigen::Isometry3d& X_OA, double reach,
                             std::vector<std::uint32_t>& out) const {
  Eigen::AlignedBox3d box;
  for (int corner = 0; corner < 8; ++corner)
    box.extend(X_OA * link.box_.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
  box.min().array() -= reach;
  box.max().array() += reach;
  const Key lo = key_of(box.min()), hi = key_of(box.max());
  const double spanned =
      double(hi.x - lo.x + 1) * double(hi.y - lo.y + 1) * double(hi.z - lo.z + 1);
  auto take = [&](const std::vector<std::uint32_t>& cells) {
    for (std::uint32_t i : cells)
      if (between(cells_[i], box) == 0.0) out.push_back(i);
  };
  if (spanned > double(buckets_.size())) {
    for (const auto& [key, cells] : buckets_) take(cells);
  } else {
    for (std::int64_t x = lo.x; x <= hi.x; ++x)
      for (std::int64_t y = lo.y; y <= hi.y; ++y)
        for (std::int64_t z = lo.z; z <= hi.z; ++z) {
          const auto it = buckets_.find({x, y, z});
          if (it != buckets_.end()) take(it->second);
        }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (link.cover_.empty()) return;
  // The mesh's surface lies in the cover's union: a cell beyond reach of every ball is
  // beyond reach of the mesh.
  std::vector<Sphere> posed;
  for (const Link::Group& g : link.cover_) posed.push_back({X_OA * g.bound.center, g.bound.radius});
  std::vector<std::vector<Sphere>> balls(link.cover_.size());
  auto near = [&](const ::fcl::AABBd& cell) {
    for (std::size_t k = 0; k < posed.size(); ++k) {
      if (to_cube(posed[k].center, cell) > posed[k].radius + reach) continue;
      if (balls[k].empty())
        for (const Sphere& s : link.cover_[k].balls)
          balls[k].push_back({X_OA * s.center, s.radius});
      for (const Sphere& s : balls[k])
        if (to_cube(s.center, cell) <= s.radius + reach) return true;
    }
    return false;
  };
  out.erase(
      std::remove_if(out.begin(), out.end(), [&](std::uint32_t i) { return !near(cells_[i]); }),
      out.end());
}

double OctreeCells::distance(const Link& link, const Eigen::Isometry3d& X_WA, double margin) const {
  if (!std::isfinite(margin) || margin < 0.0)
    throw std::invalid_argument("OctreeCells::distance: margin must be finite and >= 0");
  if (!X_WA.matrix().allFinite())
    throw std::invalid_argument("OctreeCells::distance: the link's pose is not finite");
  double best = std::nextafter(margin, std::numeric_limits<double>::infinity());
  if (cells_.empty()) return best;
  std::vector<std::uint32_t> near;
  candidates(link, X_WO_.inverse() * X_WA, margin + kGjkSlack, near);
  for (std::uint32_t i : near) {
    ::fcl::Boxd box;
    ::fcl::Transform3d X_WC;
    ::fcl::constructBox(cells_[i], X_WO_, box, X_WC);
    ::fcl::DistanceRequestd request;
    ::fcl::DistanceResultd result;
    result.min_distance = best;  // FCL prunes at it: only closer pairs are reported
    best = std::min(best, ::fcl::distance(link.mesh_, X_WA, &box, X_WC, request, result));
  }
  return best;
}

std::unique_ptr<const OctreeCells> octree_cells_of(const ::fcl::CollisionGeometryd& g,
                                                   const Eigen::Isometry3d& X_WO) {
#if FCL_HAVE_OCTOMAP
  if (g.getNodeType() == ::fcl::GEOM_OCTREE)
    return std::make_unique<const OctreeCells>(static_cast<const ::fcl::OcTree<double>&>(g), X_WO);
#endif
  return nullptr;
}

}  // namespace medspheres::fcl
