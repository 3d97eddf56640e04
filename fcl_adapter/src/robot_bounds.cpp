// A robot's links as bounded geometries, posed by forward kinematics, against a scene of
// FCL objects and against itself: each pair goes to bounded_geometry.h's queries.

#include "medspheres/fcl/robot_bounds.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

#include "medspheres/error.h"

namespace medspheres::fcl {
namespace {

using IndexPair = std::pair<std::size_t, std::size_t>;

IndexPair ordered(std::size_t a, std::size_t b) {
  return a < b ? IndexPair{a, b} : IndexPair{b, a};
}

// The pairs of link indices (kinematics order) that self-collision skips.
std::set<IndexPair> skipped_links(
    const RobotModel& model, const KinematicTree& tree,
    const std::vector<std::pair<std::string, std::string>>& disabled) {
  std::set<IndexPair> out;
  for (const Joint& j : model.joints)
    out.insert(ordered(tree.link_index(j.parent), tree.link_index(j.child)));
  for (const auto& [a, b] : disabled) {
    for (const std::string* name : {&a, &b})
      if (model.find_link(*name) == nullptr)
        throw InputError(*name, "a disabled collision pair names a link the robot does not have");
    out.insert(ordered(tree.link_index(a), tree.link_index(b)));
  }
  return out;
}

void add_minimum(DistanceBounds& m, const DistanceBounds& b) {
  m.lower = std::min(m.lower, b.lower);
  m.upper = std::min(m.upper, b.upper);
  m.stats.bv_tests += b.stats.bv_tests;
  m.stats.leaf_tests += b.stats.leaf_tests;
}

// Calls on_scene(link, object) for every geometry and scene object, then, with
// include_self, on_self(a, b) for every self-collision pair, until one returns true.
template <class S, class P>
void visit_pairs(const RobotBounds& robot, const std::vector<const ::fcl::CollisionObjectd*>& scene,
                 bool include_self, S&& on_scene, P&& on_self) {
  for (std::size_t o = 0; o < scene.size(); ++o)
    if (scene[o] == nullptr || scene[o]->collisionGeometry() == nullptr)
      throw std::invalid_argument("robot bounds: scene object " + std::to_string(o) +
                                  " is null or has no geometry");
  for (std::size_t l = 0; l < robot.geometries().size(); ++l)
    for (std::size_t o = 0; o < scene.size(); ++o)
      if (on_scene(l, o)) return;
  if (include_self)
    for (const auto& [a, b] : robot.self_pairs())
      if (on_self(a, b)) return;
}

}  // namespace

RobotBounds::RobotBounds(const RobotModel& model,
                         const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes,
                         const std::vector<std::pair<std::string, std::string>>& disabled,
                         const BoundedGeometryOptions& options)
    : tree_(model) {
  for (const Link& link : model.links) {
    const LinkSpheres& s = link.spheres;
    if (s.inner.empty() && s.outer.empty()) continue;
    const auto mesh = meshes.find(link.name);
    geometries_.push_back(BoundedGeometry::from_link(
        link.name, s, mesh != meshes.end() ? mesh->second : nullptr, options));
    link_of_.push_back(tree_.link_index(link.name));
  }
  const std::set<IndexPair> skip = skipped_links(model, tree_, disabled);
  for (std::size_t i = 0; i < geometries_.size(); ++i)
    for (std::size_t k = i + 1; k < geometries_.size(); ++k)
      if (skip.count(ordered(link_of_[i], link_of_[k])) == 0) self_pairs_.emplace_back(i, k);
}

std::vector<::fcl::Transform3d> RobotBounds::poses(const Eigen::VectorXd& q,
                                                   const Eigen::Isometry3d& X_WB) const {
  const std::vector<Eigen::Isometry3d> all = tree_.link_poses(q, X_WB);
  std::vector<::fcl::Transform3d> out;
  out.reserve(link_of_.size());
  for (std::size_t l : link_of_) out.push_back(all[l]);
  return out;
}

RobotBoundsResult robot_bounds(const RobotBounds& robot, const Eigen::VectorXd& q,
                               const std::vector<const ::fcl::CollisionObjectd*>& scene,
                               bool include_self, bool per_pair, const Eigen::Isometry3d& X_WB) {
  const std::vector<::fcl::Transform3d> X = robot.poses(q, X_WB);
  const std::vector<BoundedGeometry>& g = robot.geometries();
  RobotBoundsResult out;
  auto record = [&](std::size_t link, std::size_t other, bool self, const BoundsResult& r) {
    add_minimum(out.minimum, r.bounds);
    out.certified = out.certified && r.certified;
    if (per_pair) out.pairs.push_back({link, other, self, r.bounds});
  };
  out.minimum.lower = out.minimum.upper;  // infinity: no pair yet
  visit_pairs(
      robot, scene, include_self,
      [&](std::size_t l, std::size_t o) {
        const ::fcl::CollisionObjectd& obj = *scene[o];
        record(l, o, false,
               distance_bounds(g[l], X[l], *obj.collisionGeometry(), obj.getTransform()));
        return false;
      },
      [&](std::size_t a, std::size_t b) {
        record(a, b, true, distance_bounds(g[a], X[a], g[b], X[b]));
        return false;
      });
  return out;
}

RobotCollideResult robot_collide(const RobotBounds& robot, const Eigen::VectorXd& q,
                                 const std::vector<const ::fcl::CollisionObjectd*>& scene,
                                 bool include_self, double margin, const Eigen::Isometry3d& X_WB) {
  const std::vector<::fcl::Transform3d> X = robot.poses(q, X_WB);
  const std::vector<BoundedGeometry>& g = robot.geometries();
  RobotCollideResult out;
  // Returns true when the answer is known (a colliding pair).
  auto record = [&](const CollideResult& c) {
    ++out.pairs_tested;
    if (c.path == AnswerPath::mesh) ++out.mesh_fallbacks;
    out.certified = out.certified && c.certified;
    if (c.verdict == BoundsVerdict::undecided) out.verdict = BoundsVerdict::undecided;
    if (c.verdict != BoundsVerdict::colliding) return false;
    out.verdict = BoundsVerdict::colliding;
    return true;
  };
  visit_pairs(
      robot, scene, include_self,
      [&](std::size_t l, std::size_t o) {
        const ::fcl::CollisionObjectd& obj = *scene[o];
        return record(collide(g[l], X[l], *obj.collisionGeometry(), obj.getTransform(), margin));
      },
      [&](std::size_t a, std::size_t b) {
        return record(collide(g[a], X[a], g[b], X[b], margin));
      });
  return out;
}

}  // namespace medspheres::fcl
