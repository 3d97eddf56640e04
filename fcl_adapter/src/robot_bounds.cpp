// A robot's links as bounded geometries, posed by forward kinematics, against a scene of
// FCL objects and against itself: each pair goes to bounded_geometry.h's queries.

#include "medspheres/fcl/robot_bounds.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "medspheres/error.h"
#include "medspheres/sample_configurations.h"
#include "medspheres/self_pairs.h"

namespace medspheres::fcl {
namespace {

void add_minimum(DistanceBounds& m, const DistanceBounds& b) {
  m.lower = std::min(m.lower, b.lower);
  m.upper = std::min(m.upper, b.upper);
  m.stats.bv_tests += b.stats.bv_tests;
  m.stats.leaf_tests += b.stats.leaf_tests;
}

// With include_self, calls on_self(a, b) for the self-collision pairs seen colliding
// (robot.seen_colliding(); all of them without a SelfPairOrder), then on_scene(link,
// object) for every geometry and scene object, then on_self for the other self pairs,
// until one returns true. Self pairs come first: two links' sphere walks are cheap, and a
// robot's certain collision is most often with itself, which ends robot_collide before
// the scene; but a pair never seen colliding in the order's samples is less likely to
// collide than the scene, so it waits until after it.
template <class S, class P>
void visit_pairs(const RobotBounds& robot, const std::vector<const ::fcl::CollisionObjectd*>& scene,
                 bool include_self, S&& on_scene, P&& on_self) {
  for (std::size_t o = 0; o < scene.size(); ++o)
    if (scene[o] == nullptr || scene[o]->collisionGeometry() == nullptr)
      throw std::invalid_argument("robot bounds: scene object " + std::to_string(o) +
                                  " is null or has no geometry");
  const auto& self = robot.self_pairs();
  const std::size_t seen = include_self ? robot.seen_colliding() : 0;
  for (std::size_t k = 0; k < seen; ++k)
    if (on_self(self[k].first, self[k].second)) return;
  for (std::size_t l = 0; l < robot.geometries().size(); ++l)
    for (std::size_t o = 0; o < scene.size(); ++o)
      if (on_scene(l, o)) return;
  for (std::size_t k = seen; k < self.size() && include_self; ++k)
    if (on_self(self[k].first, self[k].second)) return;
}

// Each geometry's outer root ball (which contains its outer set, and so its surface, and
// its inner set, which lies inside the surface) at the poses X.
std::vector<Sphere> link_balls(const RobotBounds& robot, const std::vector<::fcl::Transform3d>& X) {
  std::vector<Sphere> out;
  out.reserve(X.size());
  for (std::size_t l = 0; l < X.size(); ++l) {
    const Sphere s = robot.geometries()[l].outer().bounding_ball(0);
    out.push_back({X[l] * s.center, s.radius});
  }
  return out;
}

// Greedy cover: item k holds in the samples holds[k]; each step takes the item holding in
// the most samples not yet covered (ties: the earlier item), while it adds at least
// min_gain (>= 1) of them, up to max_count items. Marks what it takes in covered.
std::vector<std::size_t> greedy_cover(const std::vector<std::vector<std::size_t>>& holds,
                                      std::vector<char>& covered, std::size_t min_gain,
                                      std::size_t max_count) {
  std::vector<std::size_t> out;
  while (out.size() < max_count) {
    std::size_t best = 0, best_gain = 0;
    for (std::size_t k = 0; k < holds.size(); ++k) {
      std::size_t gain = 0;
      for (std::size_t s : holds[k]) gain += covered[s] ? 0 : 1;
      if (gain > best_gain) best = k, best_gain = gain;
    }
    if (best_gain < std::max<std::size_t>(min_gain, 1)) break;
    out.push_back(best);
    for (std::size_t s : holds[best]) covered[s] = 1;
  }
  return out;
}

// The samples each candidate witness holds in (poses by sample).
std::vector<std::vector<std::size_t>> witness_holds_in(
    const std::vector<SelfWitness>& candidates,
    const std::vector<std::vector<::fcl::Transform3d>>& poses, double margin) {
  std::vector<std::vector<std::size_t>> holds(candidates.size());
  for (std::size_t c = 0; c < candidates.size(); ++c)
    for (std::size_t s = 0; s < poses.size(); ++s)
      if (witness_holds(candidates[c], poses[s], margin)) holds[c].push_back(s);
  return holds;
}

}  // namespace

bool witness_holds(const SelfWitness& w, const std::vector<::fcl::Transform3d>& X, double margin) {
  return balls_within({X[w.a] * w.in_a.center, w.in_a.radius},
                      {X[w.b] * w.in_b.center, w.in_b.radius}, margin);
}

std::vector<Eigen::VectorXd> sample_configurations(const RobotModel& model,
                                                   const KinematicTree& tree, std::size_t n,
                                                   unsigned seed) {
  return medspheres::sample_configurations(model, tree.joint_names(), n, seed);
}

// Greedy: each step takes the pair certainly colliding in the most samples that no pair
// taken so far collides in (ties: the earlier pair), until no pair adds one.
void RobotBounds::order_self_pairs(const RobotModel& model, const SelfPairOrder& order) {
  if (!std::isfinite(order.margin) || order.margin < 0.0)
    throw std::invalid_argument("SelfPairOrder: margin must be finite and >= 0");
  const std::vector<Eigen::VectorXd> samples =
      sample_configurations(model, tree_, order.samples, order.seed);
  std::vector<std::vector<std::size_t>> hits(self_pairs_.size());  // samples, by pair
  std::vector<std::vector<::fcl::Transform3d>> X(samples.size());
  std::set<std::array<std::intptr_t, 3>> named;  // (pair, inner sphere of a, of b)
  for (std::size_t s = 0; s < samples.size(); ++s) {
    X[s] = poses(samples[s], Eigen::Isometry3d::Identity());
    const std::vector<Sphere> balls = link_balls(*this, X[s]);
    for (std::size_t k = 0; k < self_pairs_.size(); ++k) {
      const auto [a, b] = self_pairs_[k];
      if (balls_apart(balls[a], balls[b], order.margin)) continue;
      const CollideResult c =
          decide(geometries_[a], X[s][a], geometries_[b], X[s][b], order.margin);
      if (c.verdict != BoundsVerdict::colliding) continue;
      hits[k].push_back(s);
      if (c.bounds.upper_a >= 0)
        named.insert({static_cast<std::intptr_t>(k), c.bounds.upper_a, c.bounds.upper_b});
    }
  }
  std::vector<SelfWitness> candidates;
  for (const auto& [k, i, j] : named) {
    const auto [a, b] = self_pairs_[static_cast<std::size_t>(k)];
    candidates.push_back({a, b, geometries_[a].inner().sphere(static_cast<std::size_t>(i)),
                          geometries_[b].inner().sphere(static_cast<std::size_t>(j))});
  }
  // The witnesses first; then the pairs, first over the samples no witness holds in
  // (robot_collide walks pairs only then), then over the rest.
  std::vector<char> covered(samples.size(), 0);
  for (std::size_t c : greedy_cover(witness_holds_in(candidates, X, order.margin), covered,
                                    samples.size() / 2000, order.max_witnesses))
    witnesses_.push_back(candidates[c]);
  std::vector<std::size_t> seen = greedy_cover(hits, covered, 1, hits.size());
  std::vector<char> by_seen(samples.size(), 0);
  for (std::size_t k : seen)
    for (std::size_t s : hits[k]) by_seen[s] = 1;
  for (std::size_t k : greedy_cover(hits, by_seen, 1, hits.size())) seen.push_back(k);
  std::vector<char> taken(self_pairs_.size(), 0);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t k : seen) {
    taken[k] = 1;
    out.push_back(self_pairs_[k]);
  }
  seen_colliding_ = out.size();
  for (std::size_t k = 0; k < self_pairs_.size(); ++k)
    if (!taken[k]) out.push_back(self_pairs_[k]);
  self_pairs_ = std::move(out);
}

RobotBounds::RobotBounds(const RobotModel& model,
                         const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes,
                         const std::vector<std::pair<std::string, std::string>>& disabled,
                         const BoundedGeometryOptions& options, const SelfPairOrder& order)
    : tree_(model) {
  for (const Link& link : model.links) {
    const LinkSpheres& s = link.spheres;
    if (s.inner.empty() && s.outer.empty()) continue;
    const auto mesh = meshes.find(link.name);
    geometries_.push_back(BoundedGeometry::from_link(
        link.name, s, mesh != meshes.end() ? mesh->second : nullptr, options));
    link_of_.push_back(tree_.link_index(link.name));
  }
  const std::set<LinkPair> skip = skipped_self_pairs(model, disabled);
  for (std::size_t i = 0; i < geometries_.size(); ++i)
    for (std::size_t k = i + 1; k < geometries_.size(); ++k)
      if (skip.count(ordered_pair(geometries_[i].link(), geometries_[k].link())) == 0)
        self_pairs_.emplace_back(i, k);
  seen_colliding_ = self_pairs_.size();
  if (order.samples > 0) order_self_pairs(model, order);
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
  if (!std::isfinite(margin) || margin < 0.0)
    throw std::invalid_argument("robot_collide: margin must be finite and >= 0");
  const std::vector<::fcl::Transform3d> X = robot.poses(q, X_WB);
  const std::vector<BoundedGeometry>& g = robot.geometries();
  RobotCollideResult out;
  if (include_self)
    for (const SelfWitness& w : robot.witnesses())
      if (witness_holds(w, X, margin)) {
        out.verdict = BoundsVerdict::colliding;
        out.by_witness = true;
        out.certified = g[w.a].certified() && g[w.b].certified();
        return out;
      }
  const std::vector<Sphere> links = link_balls(robot, X);
  // By scene object, by link: whether the link's ball may be within the margin of it (made
  // at the object's first pair).
  std::vector<std::vector<char>> near(scene.size());
  struct Open {
    std::size_t link, other;
    bool self;
    CollideResult decided;
  };
  std::vector<Open> open;  // undecided by the spheres
  // First the spheres alone, for every pair: one certainly colliding pair decides.
  auto record = [&](std::size_t l, std::size_t o, bool self, const CollideResult& c) {
    ++out.pairs_tested;
    out.certified = out.certified && c.certified;
    if (c.verdict == BoundsVerdict::undecided) open.push_back({l, o, self, c});
    if (c.verdict != BoundsVerdict::colliding) return false;
    out.verdict = BoundsVerdict::colliding;
    return true;
  };
  visit_pairs(
      robot, scene, include_self,
      [&](std::size_t l, std::size_t o) {
        const ::fcl::CollisionObjectd& obj = *scene[o];
        if (near[o].empty()) near[o] = balls_near(obj, links, margin);
        if (!near[o][l]) return false;
        return record(l, o, false,
                      decide(g[l], X[l], *obj.collisionGeometry(), obj.getTransform(), margin));
      },
      [&](std::size_t a, std::size_t b) {
        if (balls_apart(links[a], links[b], margin)) return false;
        return record(a, b, true, decide(g[a], X[a], g[b], X[b], margin));
      });
  if (out.verdict == BoundsVerdict::colliding) return out;
  // Then the exact meshes for the undecided pairs, until one collides.
  for (const Open& p : open) {
    CollideResult c;
    if (p.self) {
      c = settle(p.decided, g[p.link], X[p.link], g[p.other], X[p.other], margin);
    } else {
      const ::fcl::CollisionObjectd& obj = *scene[p.other];
      c = settle(p.decided, g[p.link], X[p.link], *obj.collisionGeometry(), obj.getTransform(),
                 margin);
    }
    if (c.path == AnswerPath::mesh) ++out.mesh_fallbacks;
    if (c.verdict == BoundsVerdict::undecided) out.verdict = BoundsVerdict::undecided;
    if (c.verdict == BoundsVerdict::colliding) {
      out.verdict = BoundsVerdict::colliding;
      break;
    }
  }
  return out;
}

}  // namespace medspheres::fcl
