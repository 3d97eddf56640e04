// bench_robot's exact side (robot_bench_exact.h).

#include "robot_bench_exact.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

#include <fcl/fcl.h>

namespace medspheres::bench {
namespace {

double successor(double x) {
  return std::nextafter(x, std::numeric_limits<double>::infinity());
}

}  // namespace

// The distance from the sphere object s to the mesh object m when m has a solid: 0 when the
// solid holds the centre, else the centre's distance to the triangles (MeshQuery) less the
// radius, at least 0; none for other pairs. (FCL's own sphere-to-mesh distance, fcl 0.7,
// leaves a triangle that meets the ball unset, so it is not asked.)
std::optional<double> ExactRobot::sphere_to_solid(const ::fcl::CollisionObjectd* s,
                                                  const ::fcl::CollisionObjectd* m) const {
  if (s->getObjectType() != ::fcl::OT_GEOM || s->getNodeType() != ::fcl::GEOM_SPHERE)
    return std::nullopt;
  const auto solid = solids_.find(m->collisionGeometry().get());
  if (solid == solids_.end()) return std::nullopt;
  const Eigen::Vector3d c = m->getTransform().inverse() * s->getTranslation();
  if (solid->second->inside(c)) return 0;
  const double r = static_cast<const ::fcl::Sphered&>(*s->collisionGeometry()).radius;
  return std::max(solid->second->closest_point(c).distance() - r, 0.0);
}

// FCL's distance, or a value >= `below` when the pair is not closer than `below` (a
// preset min_distance, which FCL's traversals prune at); negative answers clamped to 0; a
// sphere against a mesh with a solid by sphere_to_solid.
double ExactRobot::pair_distance(const ::fcl::CollisionObjectd* a, const ::fcl::CollisionObjectd* b,
                                 double below) const {
  if (const std::optional<double> d = sphere_to_solid(a, b)) return *d;
  if (const std::optional<double> d = sphere_to_solid(b, a)) return *d;
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  result.min_distance = below;
  return std::max(::fcl::distance(a, b, request, result), 0.0);
}

ExactRobot::ExactRobot(const fcl::RobotBounds& robot, const std::map<std::string, ExactLink>& links,
                       const std::vector<const ::fcl::CollisionObjectd*>& scene, Solids solids,
                       bool skip_beyond)
    : robot_(robot), scene_(scene), solids_(std::move(solids)), skip_beyond_(skip_beyond) {
  for (const fcl::BoundedGeometry& g : robot.geometries()) {
    std::vector<Part> parts;
    const auto it = links.find(g.link());
    if (it != links.end()) {
      // FCL's objects hold non-const geometry; the meshes are only read.
      if (it->second.mesh)
        parts.push_back({std::make_unique<::fcl::CollisionObjectd>(
                             std::const_pointer_cast<fcl::MeshModel>(it->second.mesh)),
                         ::fcl::Transform3d::Identity()});
      for (const Sphere& s : it->second.spheres) {
        ::fcl::Transform3d X = ::fcl::Transform3d::Identity();
        X.translation() = s.center;
        parts.push_back(
            {std::make_unique<::fcl::CollisionObjectd>(std::make_shared<::fcl::Sphered>(s.radius)),
             X});
      }
    }
    if (parts.empty()) ++missing_;
    links_.push_back(std::move(parts));
  }
}

void ExactRobot::pose(const std::vector<::fcl::Transform3d>& X) {
  for (std::size_t l = 0; l < links_.size(); ++l)
    for (Part& p : links_[l]) {
      p.object->setTransform(X[l] * p.X_LP);
      p.object->computeAABB();
    }
}

void ExactRobot::add(std::vector<Candidate>& out, const ::fcl::CollisionObjectd* a,
                     const ::fcl::CollisionObjectd* b, std::size_t link, std::size_t other,
                     double below) const {
  const double d = a->getAABB().distance(b->getAABB());
  if (d <= below) out.push_back({d, a, b, link, other});
}

// The pairs whose AABBs are not farther apart than `below`, in RobotBounds' order: the self
// pairs [self_from, self_to), then the scene pairs when include_scene.
std::vector<ExactRobot::Candidate> ExactRobot::candidates(bool include_scene, std::size_t self_from,
                                                          std::size_t self_to, double below) const {
  std::vector<Candidate> out;
  for (std::size_t k = self_from; k < self_to; ++k) {
    const auto [a, b] = robot_.self_pairs()[k];
    for (const Part& pa : links_[a])
      for (const Part& pb : links_[b]) add(out, pa.object.get(), pb.object.get(), a, b, below);
  }
  if (!include_scene) return out;
  // With skip_beyond_, each object's balls_near over every part's bounding ball.
  std::vector<std::vector<char>> near;
  if (skip_beyond_ && std::isfinite(below)) {
    std::vector<Sphere> balls;
    for (const std::vector<Part>& parts : links_)
      for (const Part& p : parts) {
        const ::fcl::CollisionGeometryd& g = *p.object->collisionGeometry();
        balls.push_back({p.object->getTransform() * g.aabb_center, g.aabb_radius});
      }
    for (const ::fcl::CollisionObjectd* o : scene_)
      near.push_back(fcl::balls_near(*o, balls, below));
  }
  std::size_t first = 0;  // index of the link's first part in the balls
  for (std::size_t l = 0; l < links_.size(); first += links_[l++].size())
    for (std::size_t o = 0; o < scene_.size(); ++o)
      for (std::size_t k = 0; k < links_[l].size(); ++k)
        if (near.empty() || near[o][first + k])
          add(out, links_[l][k].object.get(), scene_[o], l, o, below);
  return out;
}

bool ExactRobot::collide(const std::vector<::fcl::Transform3d>& X, bool include_self,
                         double margin) {
  pose(X);
  const double above = successor(margin);
  // As robot_collide: the self pairs seen colliding (all without a SelfPairOrder), the
  // scene, the other self pairs; each group's candidates only when no earlier pair collides.
  const std::size_t n = include_self ? robot_.self_pairs().size() : 0;
  const std::size_t seen = std::min(robot_.seen_colliding(), n);
  for (const auto& [scene, from, to] :
       {std::tuple<bool, std::size_t, std::size_t>{false, 0, seen}, {true, 0, 0}, {false, seen, n}})
    for (const Candidate& c : candidates(scene, from, to, margin))
      if (pair_distance(c.a, c.b, above) <= margin) return true;
  return false;
}

std::size_t ExactRobot::pairs_within(const std::vector<::fcl::Transform3d>& X,
                                     const std::vector<char>& use, bool include_self,
                                     double margin) {
  pose(X);
  const double above = successor(margin);
  std::size_t found = 0;
  if (std::find(use.begin(), use.end(), 1) != use.end())
    for (const Candidate& c : candidates(true, 0, 0, margin))
      if (use[c.other] && pair_distance(c.a, c.b, above) <= margin) ++found;
  if (include_self)
    for (const Candidate& c : candidates(false, 0, robot_.self_pairs().size(), margin))
      if (pair_distance(c.a, c.b, above) <= margin) ++found;
  return found;
}

double ExactRobot::distance(const std::vector<::fcl::Transform3d>& X, bool include_self) {
  pose(X);
  std::vector<Candidate> c = candidates(true, 0, include_self ? robot_.self_pairs().size() : 0,
                                        std::numeric_limits<double>::infinity());
  std::sort(c.begin(), c.end(), [](const Candidate& a, const Candidate& b) {
    return a.aabb_distance < b.aabb_distance;
  });
  double best = std::numeric_limits<double>::infinity();
  for (const Candidate& p : c) {
    if (p.aabb_distance >= best) break;  // no later pair can be closer
    best = std::min(best, pair_distance(p.a, p.b, best));
    if (best <= 0.0) break;
  }
  return best;
}

double ExactRobot::pair(const std::vector<::fcl::Transform3d>& X, std::size_t link,
                        std::size_t other, bool self) {
  pose(X);
  double best = std::numeric_limits<double>::infinity();
  for (const Part& p : links_[link]) {
    if (!self) best = std::min(best, pair_distance(p.object.get(), scene_[other], best));
    if (self)
      for (const Part& q : links_[other])
        best = std::min(best, pair_distance(p.object.get(), q.object.get(), best));
  }
  return best;
}

std::vector<std::pair<std::size_t, std::size_t>> ExactRobot::self_pairs_within(
    const std::vector<::fcl::Transform3d>& X, double margin) {
  pose(X);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  const double above = successor(margin);
  for (const Candidate& c : candidates(false, 0, robot_.self_pairs().size(), margin))
    if (pair_distance(c.a, c.b, above) <= margin &&
        (out.empty() || out.back() != std::make_pair(c.link, c.other)))
      out.emplace_back(c.link, c.other);
  return out;
}

}  // namespace medspheres::bench
