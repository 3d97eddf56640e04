// medspheres::fcl::distance and collide: the dispatch of pairs with a sphere set to the
// sphere tree, the ProximityTarget views of FCL's geometries (BVHModel of every BV type,
// primitives, octree), and the forwarding of every other pair to libfcl. FCL's heavy
// templates live in this one translation unit.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcl/config.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#if FCL_HAVE_OCTOMAP
#include <fcl/geometry/octree/octree.h>
#endif

#include "fcl_bv_rss.h"
#include "fcl_dispatch.h"
#include "fcl_geometry_visit.h"
#include "medspheres/fcl/sphere_set_geometry.h"
#include "medspheres/proximity_target.h"
#include "medspheres/sphere_tree.h"
#include "medspheres/triangle_tree.h"
#include "pair_beyond.h"

namespace medspheres::fcl {
namespace {

using detail::rss_of;
using detail::Shape;
using detail::Unsupported;
using detail::visit_geometry;

// The narrowphase settings of the caller's request, passed on to FCL's sphere tests.
struct Narrowphase {
  ::fcl::GJKSolverType solver = ::fcl::GST_LIBCCD;
  double distance_tolerance = 1e-6;
  double gjk_tolerance = 1e-6;
};

// --- targets ----------------------------------------------------------------------------

// An fcl::BVHModel of triangles, traversed through its own hierarchy.
template <class BV>
class BvhTarget final : public ProximityTarget {
 public:
  // The model must have no bvh_problem (checked by the dispatch).
  explicit BvhTarget(const ::fcl::BVHModel<BV>& model) : model_(model) {}

  std::optional<TargetNode> root() const override {
    if (model_.getModelType() != ::fcl::BVH_MODEL_TRIANGLES || model_.getNumBVs() == 0)
      return std::nullopt;
    return node(0);
  }

  int children(const TargetNode& n, TargetNode* out) const override {
    const ::fcl::BVNode<BV>& bv = model_.getBV(static_cast<int>(n.handle));
    if (bv.isLeaf()) return 0;
    out[0] = node(bv.leftChild());
    out[1] = node(bv.rightChild());
    return 2;
  }

  BallProximity ball_proximity(const TargetNode& leaf, const Eigen::Vector3d& p_BC,
                               double radius) const override {
    const ::fcl::Triangle& t = model_.tri_indices[leaf.primitive];
    return ball_triangle_proximity(p_BC, radius, model_.vertices[t[0]], model_.vertices[t[1]],
                                   model_.vertices[t[2]]);
  }

 private:
  TargetNode node(int index) const {
    const ::fcl::BVNode<BV>& bv = model_.getBV(index);
    TargetNode n;
    n.handle = index;
    n.is_leaf = bv.isLeaf();
    if (n.is_leaf)
      n.primitive = bv.primitiveId();
    else
      n.bounds = rss_of(bv.bv);
    return n;
  }

  const ::fcl::BVHModel<BV>& model_;
};

// The answer of a solid or surface primitive S, posed at X_BS in frame B, to a ball, from
// FCL's own sphere narrowphase: the distance when separated, else the contact.
BallProximity ball_vs_shape(const ::fcl::CollisionGeometryd& shape, const ::fcl::Transform3d& X_BS,
                            const Eigen::Vector3d& p_BC, double radius, const Narrowphase& np) {
  const ::fcl::Sphered ball(radius);
  ::fcl::Transform3d X_BC = ::fcl::Transform3d::Identity();
  X_BC.translation() = p_BC;
  ::fcl::DistanceRequestd dreq(true, false, 0.0, 0.0, np.distance_tolerance, np.solver);
  ::fcl::DistanceResultd dres;
  const double d = ::fcl::distance<double>(&ball, X_BC, &shape, X_BS, dreq, dres);
  BallProximity out;
  if (d > 0.0) {
    out.distance = d;
    Eigen::Vector3d n = dres.nearest_points[1] - dres.nearest_points[0];
    if (!(n.norm() > 0.0)) n = dres.nearest_points[1] - p_BC;
    if (n.norm() > 0.0) out.normal = n.normalized();
    return out;
  }
  ::fcl::CollisionRequestd creq(1, true, 1, false, true, np.solver, np.gjk_tolerance);
  ::fcl::CollisionResultd cres;
  ::fcl::collide<double>(&ball, X_BC, &shape, X_BS, creq, cres);
  if (cres.isCollision()) {
    const ::fcl::Contactd& c = cres.getContact(0);
    out.distance = -std::max(c.penetration_depth, 0.0);
    if (c.normal.norm() > 0.0) out.normal = c.normal.normalized();
  } else {
    // The two tests disagree at the boundary (GJK tolerances): touching.
    out.distance = 0.0;
  }
  return out;
}

// The answer of the solid axis-aligned box [lo, hi] of frame B to a ball that it does not
// touch: the box's nearest point to the centre is the centre clamped to the box, so the
// distance is |C - clamp(C)| - r along the direction to that point (FCL's
// sphereBoxDistance, without building the two shapes). Nothing when the ball touches or
// overlaps the box: FCL's contact answers that.
std::optional<BallProximity> ball_apart_from_box(const Eigen::Vector3d& lo,
                                                 const Eigen::Vector3d& hi,
                                                 const Eigen::Vector3d& p_BC, double radius) {
  const Eigen::Vector3d to_box = p_BC.cwiseMax(lo).cwiseMin(hi) - p_BC;
  const double d = to_box.norm();
  if (!(d > radius)) return std::nullopt;
  BallProximity out;
  out.distance = d - radius;
  out.normal = to_box / d;
  return out;
}

// A lone FCL primitive, at the identity in frame B.
class ShapeTarget final : public ProximityTarget {
 public:
  ShapeTarget(const ::fcl::CollisionGeometryd& shape, const Narrowphase& np)
      : shape_(shape), np_(np) {}

  std::optional<TargetNode> root() const override {
    TargetNode n;
    n.is_leaf = true;
    n.primitive = ::fcl::Contactd::NONE;
    return n;
  }

  int children(const TargetNode&, TargetNode*) const override { return 0; }

  BallProximity ball_proximity(const TargetNode&, const Eigen::Vector3d& p_BC,
                               double radius) const override {
    BallProximity out;
    switch (shape_.getNodeType()) {
      case ::fcl::GEOM_HALFSPACE: {
        // Solid {x : n.x <= d}; FCL's normal for a sphere against it is -n.
        const auto& h = static_cast<const ::fcl::Halfspaced&>(shape_);
        out.distance = (h.n.dot(p_BC) - h.d) - radius;
        out.normal = -h.n;
        return out;
      }
      case ::fcl::GEOM_PLANE: {
        // Surface {x : n.x = d}; FCL's normal is -n on the positive side, n otherwise.
        const auto& p = static_cast<const ::fcl::Planed&>(shape_);
        const double s = p.n.dot(p_BC) - p.d;
        out.distance = std::abs(s) - radius;
        out.normal = s > 0.0 ? Eigen::Vector3d(-p.n) : Eigen::Vector3d(p.n);
        return out;
      }
      case ::fcl::GEOM_BOX: {
        const Eigen::Vector3d half = 0.5 * static_cast<const ::fcl::Boxd&>(shape_).side;
        if (const auto apart = ball_apart_from_box(-half, half, p_BC, radius)) return *apart;
        return ball_vs_shape(shape_, ::fcl::Transform3d::Identity(), p_BC, radius, np_);
      }
      default:
        return ball_vs_shape(shape_, ::fcl::Transform3d::Identity(), p_BC, radius, np_);
    }
  }

 private:
  const ::fcl::CollisionGeometryd& shape_;
  Narrowphase np_;
};

#if FCL_HAVE_OCTOMAP
// An fcl::OcTree: its occupied cells as boxes, with FCL's rules (internal cells must be
// occupied to be opened, leaf cells must be occupied to count). A node's bounds are its
// cube (TargetNode::box_half), and also the cube's RSS (rectangle through the cube's
// middle, radius half its side), from which the cube is recovered exactly. A child's cube
// is computed as fcl::computeChildBV computes it, so cubes and cell ids are FCL's.
//
// Chains: a cell with one occupied child holds only that child's cells. An octomap's root
// lies 16 levels above its leaves, and a cloud that straddles a coordinate plane through
// the octree's origin leaves a chain of ten or more single cells below each of the root's
// children; so a cell's children are those of the first cell down its chain that has
// several (or is a leaf), and every cell of the chain is walked once, when it is opened.
class OctreeTarget final : public ProximityTarget {
 public:
  using Cell = ::fcl::OcTreed::OcTreeNode;

  OctreeTarget(const ::fcl::OcTreed& tree, const Narrowphase& np) : tree_(tree), np_(np) {}

  std::optional<TargetNode> root() const override {
    const Cell* root = tree_.getRoot();
    if (root == nullptr || !tree_.isNodeOccupied(root)) return std::nullopt;
    // The root's bounds: the smallest cell that holds every occupied cell.
    const ::fcl::AABBd bv = tree_.getRootBV();
    Fork forks[2];
    const Fork& f = fork_below(root, Cube{bv.min_, bv.max_}, forks);
    TargetNode n;
    set_node(n, f.cell, f.cube);
    return n;
  }

  int children(const TargetNode& n, TargetNode* out) const override {
    Fork forks[2];
    const Fork& f = fork_below(reinterpret_cast<const Cell*>(n.handle), cube_of(n.bounds), forks);
    for (int k = 0; k < f.count; ++k) set_node(out[k], f.kids[k], child_cube(f.cube, f.which[k]));
    return f.count;
  }

  BallProximity ball_proximity(const TargetNode& leaf, const Eigen::Vector3d& p_BC,
                               double radius) const override {
    const Cube c = cube_of(leaf.bounds);
    if (const auto apart = ball_apart_from_box(c.lo, c.hi, p_BC, radius)) return *apart;
    const ::fcl::Boxd shape(c.hi - c.lo);
    ::fcl::Transform3d X_BS = ::fcl::Transform3d::Identity();
    X_BS.translation() = 0.5 * (c.lo + c.hi);
    return ball_vs_shape(shape, X_BS, p_BC, radius, np_);
  }

 private:
  // A cell's cube [lo, hi] (fcl::AABB's min_ and max_).
  struct Cube {
    Eigen::Vector3d lo, hi;
  };

  // A cell, its cube and its occupied children (child index `which`; the first `count`
  // entries are set); `any`: whether it has children at all, occupied or not.
  struct Fork {
    const Cell* cell;
    Cube cube;
    int count;
    bool any;
    const Cell* kids[8];
    unsigned int which[8];
  };

  void enumerate(Fork& f) const {
    f.count = 0;
    f.any = false;
    for (unsigned int i = 0; i < 8; ++i) {
      if (!tree_.nodeChildExists(f.cell, i)) continue;
      f.any = true;
      const Cell* child = tree_.getNodeChild(f.cell, i);
      if (!tree_.isNodeOccupied(child)) continue;
      f.kids[f.count] = child;
      f.which[f.count++] = i;
    }
  }

  // The first cell down the chain from `cell` (itself included) that is a leaf or has other
  // than one occupied child, or the last cell of the chain whose one child is a leaf; in one
  // of the two forks given.
  const Fork& fork_below(const Cell* cell, const Cube& cube, Fork (&forks)[2]) const {
    Fork* f = &forks[0];
    Fork* next = &forks[1];
    f->cell = cell;
    f->cube = cube;
    enumerate(*f);
    while (f->count == 1) {
      next->cell = f->kids[0];
      next->cube = child_cube(f->cube, f->which[0]);
      enumerate(*next);
      if (!next->any) break;  // the one child is a leaf
      std::swap(f, next);
    }
    return *f;
  }

  // Child i's cube, with fcl::computeChildBV's arithmetic (bit k of i: the upper half
  // along axis k).
  static Cube child_cube(const Cube& c, unsigned int i) {
    Cube child;
    for (int axis = 0; axis < 3; ++axis) {
      const double mid = (c.lo[axis] + c.hi[axis]) * 0.5;
      const bool upper = (i >> axis) & 1u;
      child.lo[axis] = upper ? mid : c.lo[axis];
      child.hi[axis] = upper ? c.hi[axis] : mid;
    }
    return child;
  }

  // Assigns every field of n: the cell's handle, leaf flag, bounds and id.
  void set_node(TargetNode& n, const Cell* cell, const Cube& c) const {
    n.handle = reinterpret_cast<std::intptr_t>(cell);
    n.is_leaf = !tree_.nodeHasChildren(cell);
    n.bounds.axis.setIdentity();
    n.bounds.corner = Eigen::Vector3d(c.lo.x(), c.lo.y(), 0.5 * (c.lo.z() + c.hi.z()));
    n.bounds.length = Eigen::Vector2d(c.hi.x() - c.lo.x(), c.hi.y() - c.lo.y());
    n.bounds.radius = 0.5 * (c.hi.x() - c.lo.x());
    if (n.is_leaf)
      n.box_half.reset();
    else
      n.box_half = 0.5 * (c.hi - c.lo);
    // FCL's query cell id (see fcl::OcTree::getNodeByQueryCellId).
    n.primitive = n.is_leaf ? static_cast<std::intptr_t>(cell - tree_.getRoot()) : -1;
  }

  static Cube cube_of(const Rss& bounds) {
    return Cube{
        Eigen::Vector3d(bounds.corner.x(), bounds.corner.y(), bounds.corner.z() - bounds.radius),
        Eigen::Vector3d(bounds.corner.x() + bounds.length[0], bounds.corner.y() + bounds.length[1],
                        bounds.corner.z() + bounds.radius)};
  }

  const ::fcl::OcTreed& tree_;
  Narrowphase np_;
};
#endif

std::string node_type_name(::fcl::NODE_TYPE type) {
  return "FCL node type " + std::to_string(static_cast<int>(type));
}

// Why a BVHModel cannot be a target (a model of points, or one not finished), or an empty
// string when it can.
template <class BV>
std::string bvh_problem(const ::fcl::BVHModel<BV>& model) {
  if (model.getModelType() == ::fcl::BVH_MODEL_POINTCLOUD)
    return "medspheres::fcl: a BVHModel of points is not supported";
  if (model.getModelType() == ::fcl::BVH_MODEL_TRIANGLES &&
      model.build_state != ::fcl::BVH_BUILD_STATE_PROCESSED &&
      model.build_state != ::fcl::BVH_BUILD_STATE_UPDATED)
    return "medspheres::fcl: the BVHModel is not finished (endModel())";
  return {};
}

std::string unsupported_problem(const Unsupported& u) {
  return "medspheres::fcl: a sphere set against " + node_type_name(u.type) + " is not supported";
}

// Why a sphere set cannot be answered against g (not a sphere set) on its sphere tree, as
// the dispatch's std::invalid_argument says it, or an empty string when it can.
struct TargetProblem {
  template <class BV>
  std::string operator()(const ::fcl::BVHModel<BV>& model) const {
    return bvh_problem(model);
  }
  std::string operator()(const Shape&) const { return {}; }
#if FCL_HAVE_OCTOMAP
  std::string operator()(const ::fcl::OcTreed&) const {
    return {};
  }
#endif
  std::string operator()(const Unsupported& u) const {
    return unsupported_problem(u);
  }
};

// Calls f with the ProximityTarget view of the geometry visited; throws
// std::invalid_argument with TargetProblem's message where there is none.
template <class F>
struct TargetCall {
  using Result = std::invoke_result_t<F&, const ProximityTarget&>;
  const Narrowphase& np;
  F& f;

  template <class BV>
  Result operator()(const ::fcl::BVHModel<BV>& model) const {
    const std::string problem = bvh_problem(model);
    if (!problem.empty()) throw std::invalid_argument(problem);
    return f(BvhTarget<BV>(model));
  }
  Result operator()(const Shape& shape) const { return f(ShapeTarget(shape.geometry, np)); }
#if FCL_HAVE_OCTOMAP
  Result operator()(const ::fcl::OcTreed& tree) const {
    return f(OctreeTarget(tree, np));
  }
#endif
  Result operator()(const Unsupported& u) const {
    throw std::invalid_argument(unsupported_problem(u));
  }
};

// Calls f(target) with the ProximityTarget view of a geometry that is not a sphere set.
template <class F>
auto with_target(const ::fcl::CollisionGeometryd& g, const Narrowphase& np, F&& f) {
  return visit_geometry(g, TargetCall<F>{np, f});
}

bool finite_pose(const ::fcl::Transform3d& X) {
  return X.matrix().allFinite();
}

// Both poses finite: a finite sum of all their entries shows it at once (a non-finite
// entry makes the sum infinite or NaN); only a sum that overflows needs the entries.
bool finite_poses(const ::fcl::Transform3d& X1, const ::fcl::Transform3d& X2) {
  return std::isfinite(X1.matrix().sum() + X2.matrix().sum()) ||
         (finite_pose(X1) && finite_pose(X2));
}

// --- distance ----------------------------------------------------------------------------

// The sphere set s at X_WS against geometry g at X_WG; the result's a side is s.
TreeDistance sphere_set_distance(const SphereSetGeometry& s, const ::fcl::Transform3d& X_WS,
                                 const ::fcl::CollisionGeometryd& g, const ::fcl::Transform3d& X_WG,
                                 const DistanceOptions& options, bool is_signed,
                                 const Narrowphase& np) {
  if (const SphereSetGeometry* other = as_sphere_set(&g)) {
    return is_signed ? medspheres::signed_distance(s.tree(), X_WS, other->tree(), X_WG, options)
                     : medspheres::distance(s.tree(), X_WS, other->tree(), X_WG, options);
  }
  return with_target(g, np, [&](const ProximityTarget& target) {
    return is_signed ? medspheres::signed_distance(s.tree(), X_WS, target, X_WG, options)
                     : medspheres::distance(s.tree(), X_WS, target, X_WG, options);
  });
}

// --- collision --------------------------------------------------------------------------

std::vector<TreeContact> sphere_set_contacts(const SphereSetGeometry& s,
                                             const ::fcl::Transform3d& X_WS,
                                             const ::fcl::CollisionGeometryd& g,
                                             const ::fcl::Transform3d& X_WG,
                                             std::size_t max_contacts, const Narrowphase& np) {
  std::vector<TreeContact> out;
  if (const SphereSetGeometry* other = as_sphere_set(&g)) {
    medspheres::contacts(s.tree(), X_WS, other->tree(), X_WG, max_contacts, out);
    return out;
  }
  with_target(g, np, [&](const ProximityTarget& target) {
    return medspheres::contacts(s.tree(), X_WS, target, X_WG, max_contacts, out);
  });
  return out;
}

}  // namespace

namespace detail {

bool answered_on_spheres(const ::fcl::CollisionGeometryd* o1, const ::fcl::Transform3d& tf1,
                         const ::fcl::CollisionGeometryd* o2, const ::fcl::Transform3d& tf2) {
  if (o1 == nullptr || o2 == nullptr) return true;
  const SphereSetGeometry* s1 = as_sphere_set(o1);
  const SphereSetGeometry* s2 = as_sphere_set(o2);
  if (s1 == nullptr && s2 == nullptr) return false;
  if (!finite_pose(tf1) || !finite_pose(tf2)) return false;
  if (s1 != nullptr && s2 != nullptr) return true;
  return visit_geometry(s1 == nullptr ? *o1 : *o2, TargetProblem{}).empty();
}

void with_target_view(const ::fcl::CollisionGeometryd& g,
                      const std::function<void(const ProximityTarget&)>& f) {
  with_target(g, Narrowphase{}, f);
}

}  // namespace detail

double distance(const ::fcl::CollisionGeometryd* o1, const ::fcl::Transform3d& tf1,
                const ::fcl::CollisionGeometryd* o2, const ::fcl::Transform3d& tf2,
                const ::fcl::DistanceRequestd& request, ::fcl::DistanceResultd& result) {
  if (o1 == nullptr || o2 == nullptr)
    throw std::invalid_argument("medspheres::fcl::distance: null geometry");
  const SphereSetGeometry* s1 = as_sphere_set(o1);
  const SphereSetGeometry* s2 = as_sphere_set(o2);
  if (s1 == nullptr && s2 == nullptr)
    return ::fcl::distance<double>(o1, tf1, o2, tf2, request, result);
  if (!finite_poses(tf1, tf2))
    throw std::invalid_argument("medspheres::fcl::distance: a transform has a non-finite entry");
  // Nothing closer than a preset min_distance can be found when the bounds are farther.
  if (s1 != nullptr ? detail::pair_beyond(*s1, tf1, *o2, s2, tf2, result.min_distance)
                    : detail::pair_beyond(*s2, tf2, *o1, s1, tf1, result.min_distance))
    return result.min_distance;

  DistanceOptions options;
  options.abs_err = request.abs_err;
  options.rel_err = request.rel_err;
  options.upper_bound = result.min_distance;
  Narrowphase np;
  np.solver = request.gjk_solver_type;
  np.distance_tolerance = request.distance_tolerance;
  const bool swapped = s1 == nullptr;
  const TreeDistance d =
      swapped
          ? sphere_set_distance(*s2, tf2, *o1, tf1, options, request.enable_signed_distance, np)
          : sphere_set_distance(*s1, tf1, *o2, tf2, options, request.enable_signed_distance, np);
  if (d.found() && d.distance < result.min_distance) {
    const int b1 = static_cast<int>(swapped ? d.primitive_b : d.sphere_a);
    const int b2 = static_cast<int>(swapped ? d.sphere_a : d.primitive_b);
    if (request.enable_nearest_points) {
      result.update(d.distance, o1, o2, b1, b2, swapped ? d.p_WPb : d.p_WPa,
                    swapped ? d.p_WPa : d.p_WPb);
    } else {
      result.update(d.distance, o1, o2, b1, b2);
    }
  }
  return result.min_distance;
}

double distance(const ::fcl::CollisionObjectd* o1, const ::fcl::CollisionObjectd* o2,
                const ::fcl::DistanceRequestd& request, ::fcl::DistanceResultd& result) {
  if (o1 == nullptr || o2 == nullptr)
    throw std::invalid_argument("medspheres::fcl::distance: null collision object");
  return distance(o1->collisionGeometry().get(), o1->getTransform(), o2->collisionGeometry().get(),
                  o2->getTransform(), request, result);
}

std::size_t collide(const ::fcl::CollisionGeometryd* o1, const ::fcl::Transform3d& tf1,
                    const ::fcl::CollisionGeometryd* o2, const ::fcl::Transform3d& tf2,
                    const ::fcl::CollisionRequestd& request, ::fcl::CollisionResultd& result) {
  if (o1 == nullptr || o2 == nullptr)
    throw std::invalid_argument("medspheres::fcl::collide: null geometry");
  const SphereSetGeometry* s1 = as_sphere_set(o1);
  const SphereSetGeometry* s2 = as_sphere_set(o2);
  if (s1 == nullptr && s2 == nullptr)
    return ::fcl::collide<double>(o1, tf1, o2, tf2, request, result);
  if (!finite_poses(tf1, tf2))
    throw std::invalid_argument("medspheres::fcl::collide: a transform has a non-finite entry");
  if (request.num_max_contacts == 0) return 0;
  if (request.isSatisfied(result)) return result.numContacts();
  if (!o1->isOccupied() || !o2->isOccupied()) return result.numContacts();
  const std::size_t room = request.num_max_contacts > result.numContacts()
                               ? request.num_max_contacts - result.numContacts()
                               : 0;
  if (room == 0) return result.numContacts();
  // Touching is a contact: bounds farther apart than 0 hold none.
  if (s1 != nullptr ? detail::pair_beyond(*s1, tf1, *o2, s2, tf2, 0.0)
                    : detail::pair_beyond(*s2, tf2, *o1, s1, tf1, 0.0))
    return result.numContacts();

  Narrowphase np;
  np.solver = request.gjk_solver_type;
  np.gjk_tolerance = request.gjk_tolerance;
  const bool swapped = s1 == nullptr;
  const std::vector<TreeContact> found = swapped
                                             ? sphere_set_contacts(*s2, tf2, *o1, tf1, room, np)
                                             : sphere_set_contacts(*s1, tf1, *o2, tf2, room, np);
  for (const TreeContact& c : found) {
    const int b1 = static_cast<int>(swapped ? c.primitive_b : c.sphere_a);
    const int b2 = static_cast<int>(swapped ? c.sphere_a : c.primitive_b);
    if (request.enable_contact) {
      result.addContact(::fcl::Contactd(o1, o2, b1, b2, c.p_WC,
                                        swapped ? Eigen::Vector3d(-c.n_W) : c.n_W, c.depth));
    } else {
      result.addContact(::fcl::Contactd(o1, o2, b1, b2));
    }
  }
  return result.numContacts();
}

std::size_t collide(const ::fcl::CollisionObjectd* o1, const ::fcl::CollisionObjectd* o2,
                    const ::fcl::CollisionRequestd& request, ::fcl::CollisionResultd& result) {
  if (o1 == nullptr || o2 == nullptr)
    throw std::invalid_argument("medspheres::fcl::collide: null collision object");
  return collide(o1->collisionGeometry().get(), o1->getTransform(), o2->collisionGeometry().get(),
                 o2->getTransform(), request, result);
}

}  // namespace medspheres::fcl
