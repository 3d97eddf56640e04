// The links' exact solids and a planner's spheres, posed, pair by pair
// (link_collision_geometry.h).
#include "medspheres/robot_bake/link_collision_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "medspheres/error.h"
#include "medspheres/fcl/balls_near.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/min_enclosing_ball.h"

namespace medspheres {

namespace {

const LinkSolid* find_solid(const std::vector<LinkSolid>& solids, const std::string& link) {
  for (const LinkSolid& s : solids)
    if (s.link == link) return &s;
  return nullptr;
}

// An icosphere whose facets all lie outside the ball (c, r): the unit icosphere's least
// facet-plane distance d from its centre, scaled by r / d and rounded up.
TriangleMesh containing_icosphere(const Sphere& s) {
  const TriangleMesh unit = make_icosphere(1.0, 2);
  double d = 1.0;
  for (std::size_t t = 0; t < unit.num_triangles(); ++t) {
    const Eigen::Vector3d n =
        (unit.corner(t, 1) - unit.corner(t, 0)).cross(unit.corner(t, 2) - unit.corner(t, 0));
    d = std::min(d, std::abs(n.normalized().dot(unit.corner(t, 0))));
  }
  TriangleMesh out = unit;
  const double scale = s.radius / d * (1.0 + 1e-9);
  for (Eigen::Vector3d& v : out.vertices) v = s.center + scale * v;
  return out;
}

// The link's exact mesh in its frame: its meshed parts, and its sphere primitives as
// containing icospheres when it has meshed parts too. Empty for sphere primitives alone.
TriangleMesh exact_mesh(const LinkSolid& solid) {
  TriangleMesh mesh = solid.placed_mesh();
  if (solid.parts.empty()) return mesh;
  for (const Sphere& s : solid.spheres) {
    const TriangleMesh ico = containing_icosphere(s);
    const int base = static_cast<int>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), ico.vertices.begin(), ico.vertices.end());
    for (const auto& t : ico.triangles)
      mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return mesh;
}

// A covering set for a link without one: the least ball around its mesh's vertices (it
// holds their convex hull, so the surface) and its sphere primitives.
SphereSet enclosing_cover(const TriangleMesh& mesh, const std::vector<Sphere>& primitives) {
  std::vector<Sphere> all = primitives;
  for (const Eigen::Vector3d& v : mesh.vertices) all.push_back({v, 0.0});
  SphereSet out;
  out.spheres.push_back(min_enclosing_ball(all));
  return out;
}

}  // namespace

SolidQueryCounts& SolidQueryCounts::operator+=(const SolidQueryCounts& o) {
  queries += o.queries;
  by_ball += o.by_ball;
  by_bounds += o.by_bounds;
  mesh_queries += o.mesh_queries;
  return *this;
}

LinkSolids::LinkSolids(const RobotModel& model, const std::vector<LinkSolid>& solids)
    : geometry_(model.links.size()), balls_(model.links.size()) {
  fcl::BoundedGeometryOptions options;
  options.allow_uncertified = true;  // a cover bake records its certificate; others still hold
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    const Link& link = model.links[i];
    const LinkSolid* solid = find_solid(solids, link.name);
    if (solid == nullptr || solid->empty()) continue;
    const TriangleMesh mesh = exact_mesh(*solid);
    LinkSpheres sets = link.spheres;
    if (sets.inner.empty()) {
      if (solid->spheres.empty())
        throw InputError(link.name, "the link has no inner sphere set to bound its solid with");
      sets.inner.spheres = solid->spheres;
    }
    if (sets.outer.empty()) sets.outer = enclosing_cover(mesh, solid->spheres);
    geometry_[i].emplace(fcl::BoundedGeometry::from_link(
        link.name, sets, mesh.triangles.empty() ? nullptr : fcl::make_mesh_model(mesh), options));
    balls_[i] = geometry_[i]->outer().bounding_ball(0);
  }
}

bool LinkSolids::within(const std::vector<Eigen::Isometry3d>& X, std::size_t a, std::size_t b,
                        double margin, SolidQueryCounts* counts) const {
  SolidQueryCounts local;
  SolidQueryCounts& c = counts ? *counts : local;
  ++c.queries;
  const Sphere& ba = balls_.at(a);
  const Sphere& bb = balls_.at(b);
  if (fcl::balls_apart({X[a] * ba.center, ba.radius}, {X[b] * bb.center, bb.radius}, margin)) {
    ++c.by_ball;
    return false;
  }
  const fcl::BoundedGeometry& ga = *geometry_.at(a);
  const fcl::BoundedGeometry& gb = *geometry_.at(b);
  const fcl::CollideResult d = fcl::decide(ga, X[a], gb, X[b], margin);
  if (d.verdict != BoundsVerdict::undecided) {
    ++c.by_bounds;
    return d.verdict == BoundsVerdict::colliding;
  }
  ++c.mesh_queries;
  return fcl::settle(d, ga, X[a], gb, X[b], margin).verdict == BoundsVerdict::colliding;
}

PlannerSpheres::PlannerSpheres(const RobotModel& model, const formats::RobotSpheres& spheres,
                               const std::map<std::string, double>& buffer)
    : trees_(model.links.size()), balls_(model.links.size()), buffer_(model.links.size(), 0.0) {
  for (const Link& l : model.links) names_.push_back(l.name);
  for (const formats::LinkSphereList& l : spheres) {
    const std::size_t i = std::find(names_.begin(), names_.end(), l.link) - names_.begin();
    if (i == names_.size())
      throw InputError(l.link, "the planner's spheres name a link the robot does not have");
    if (l.spheres.empty()) continue;
    SphereSet set;
    set.spheres = l.spheres;
    trees_[i] = SphereTree(set);
    balls_[i] = trees_[i].bounding_ball(0);
  }
  *this = with_buffer(buffer);
}

PlannerSpheres PlannerSpheres::with_buffer(const std::map<std::string, double>& buffer) const {
  PlannerSpheres out = *this;
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const auto it = buffer.find(names_[i]);
    out.buffer_[i] = it == buffer.end() ? 0.0 : it->second;
  }
  return out;
}

bool PlannerSpheres::collide(const std::vector<Eigen::Isometry3d>& X, std::size_t a,
                             std::size_t b) const {
  if (trees_.at(a).empty() || trees_.at(b).empty()) return false;
  const double grow = buffer_[a] + buffer_[b];
  const Sphere& ba = balls_[a];
  const Sphere& bb = balls_[b];
  if (fcl::balls_apart({X[a] * ba.center, ba.radius}, {X[b] * bb.center, bb.radius},
                       std::max(grow, 0.0)))
    return false;
  if (grow == 0.0) return medspheres::collide(trees_[a], X[a], trees_[b], X[b]);
  if (grow < 0.0) return signed_distance(trees_[a], X[a], trees_[b], X[b]).distance <= grow;
  DistanceOptions o;
  o.upper_bound = std::nextafter(grow, std::numeric_limits<double>::infinity());
  return medspheres::distance(trees_[a], X[a], trees_[b], X[b], o).distance <= grow;
}

double PlannerSpheres::penetration(const std::vector<Eigen::Isometry3d>& X, std::size_t a,
                                   std::size_t b) const {
  if (trees_.at(a).empty() || trees_.at(b).empty()) return -std::numeric_limits<double>::infinity();
  return buffer_[a] + buffer_[b] - signed_distance(trees_[a], X[a], trees_[b], X[b]).distance;
}

}  // namespace medspheres
