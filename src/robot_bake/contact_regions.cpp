// Contact-aware covers (contact_regions.h): the regions from sampled configurations, and
// the two-pass bake.
#include "medspheres/robot_bake/contact_regions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include "medspheres/error.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/number_text.h"
#include "medspheres/sample_configurations.h"
#include "medspheres/threads.h"

namespace medspheres {

namespace {

using Poses = std::vector<Eigen::Isometry3d>;
using Points = std::vector<Eigen::Vector3d>;

// Of \p points, the first in each cell of side \p cell that holds at least \p least of them.
Points frequent(const Points& points, double cell, std::size_t least) {
  std::map<std::array<long long, 3>, std::pair<std::size_t, std::size_t>> cells;  // first, count
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector3d c = (points[k] / cell).array().floor();
    auto& slot = cells
                     .try_emplace({static_cast<long long>(c.x()), static_cast<long long>(c.y()),
                                   static_cast<long long>(c.z())},
                                  k, 0)
                     .first->second;
    ++slot.second;
  }
  std::vector<std::size_t> kept;
  for (const auto& entry : cells)
    if (entry.second.second >= least) kept.push_back(entry.second.first);
  std::sort(kept.begin(), kept.end());
  Points out;
  for (std::size_t k : kept) out.push_back(points[k]);
  return out;
}

// One point per cell of side \p cell (the first in order).
Points thinned(const Points& points, double cell) {
  return frequent(points, cell, 1);
}

// Points on every triangle of \p m at most \p step apart (a barycentric grid), thinned to
// one per cell of \p step.
Points surface_points(const TriangleMesh& m, double step) {
  Points out;
  for (std::size_t t = 0; t < m.num_triangles(); ++t) {
    const Eigen::Vector3d a = m.corner(t, 0), b = m.corner(t, 1), c = m.corner(t, 2);
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / step)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) out.push_back(a + (b - a) * i / n + (c - a) * j / n);
  }
  return thinned(out, step);
}

// A link's placed meshes (link frame), their query, surface points and bounding ball.
struct LinkSurface {
  std::unique_ptr<MeshQuery> query;
  Points points;
  Sphere ball;
};

std::optional<LinkSurface> link_surface(const LinkSolid& solid, double band) {
  if (solid.parts.empty()) return std::nullopt;
  TriangleMesh mesh = solid.placed_mesh();
  if (mesh.num_triangles() == 0) return std::nullopt;
  LinkSurface s;
  s.ball.center = mesh.bounds().center();
  for (const Eigen::Vector3d& v : mesh.vertices)
    s.ball.radius = std::max(s.ball.radius, (v - s.ball.center).norm());
  s.points = surface_points(mesh, 0.5 * band);
  s.query = std::make_unique<MeshQuery>(std::move(mesh));
  return s;
}

// The points of \p from (poses X_f) within band of \p to's surface (pose X_t), in to's frame.
Points near_points(const LinkSurface& to, const LinkSurface& from, const Eigen::Isometry3d& X_t,
                   const Eigen::Isometry3d& X_f, double band) {
  const Eigen::Isometry3d X_tf = X_t.inverse() * X_f;
  Points candidates;
  for (const Eigen::Vector3d& p : from.points) {
    const Eigen::Vector3d q = X_tf * p;
    if ((q - to.ball.center).norm() <= to.ball.radius + band) candidates.push_back(q);
  }
  Points out;
  if (candidates.empty()) return out;
  const std::vector<ClosestPoint> near = to.query->closest_points(candidates, 1);
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (near[k].distance() <= band) out.push_back(candidates[k]);
  return out;
}

// Every link's poses in each sampled configuration, the locked joints held.
std::vector<Poses> sampled_poses(const RobotModel& model, const KinematicTree& tree,
                                 const std::map<std::string, double>& locked,
                                 const ContactOptions& o) {
  const std::vector<std::string>& names = tree.joint_names();
  std::vector<Poses> out;
  for (Eigen::VectorXd q : sample_configurations(model, names, o.samples, o.seed)) {
    for (std::size_t k = 0; k < names.size(); ++k) {
      const auto it = locked.find(names[k]);
      if (it != locked.end()) q[static_cast<Eigen::Index>(k)] = it->second;
    }
    out.push_back(tree.link_poses(q));
  }
  return out;
}

}  // namespace

void validate(const ContactOptions& o) {
  if (o.samples < 1)
    throw InputError::option(ErrorKind::kOutOfRange, "contact_samples", "0", "must be >= 1");
  if (!(o.band > 0.0) || !std::isfinite(o.band))
    throw InputError::option(ErrorKind::kOutOfRange, "contact_band", number_text(o.band),
                             "must be a finite length > 0");
  if (!(o.weight >= 1.0) || !std::isfinite(o.weight))
    throw InputError::option(ErrorKind::kOutOfRange, "contact_weight", number_text(o.weight),
                             "must be finite and >= 1");
  if (!(o.min_share >= 0.0 && o.min_share <= 1.0))
    throw InputError::option(ErrorKind::kOutOfRange, "contact_min_share", number_text(o.min_share),
                             "must be in [0, 1]");
  check_threads(o.threads);
}

std::map<std::string, ProtrusionWeights> contact_regions(
    const RobotModel& model, const std::vector<LinkSolid>& solids,
    const SelfCollisionMatrix& matrix, const std::map<std::string, double>& locked,
    const ContactOptions& o) {
  validate(o);
  if (solids.size() != model.links.size())
    throw std::invalid_argument("contact_regions: one solid per model link is needed");
  const KinematicTree tree(model);  // its links in the model's order
  std::vector<std::optional<LinkSurface>> surface(solids.size());
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const LinkPairClass& p : matrix.pairs) {
    if (p.ignored) continue;
    const std::size_t a = tree.link_index(p.link1), b = tree.link_index(p.link2);
    for (std::size_t i : {a, b})
      if (!surface[i]) surface[i] = link_surface(solids[i], o.band);
    if (surface[a] && surface[b]) pairs.emplace_back(a, b);
  }
  const std::vector<Poses> poses = sampled_poses(model, tree, locked, o);
  // Per pair, the points found on each side (a's region, b's region).
  std::vector<std::array<Points, 2>> found(pairs.size());
  const long long n = static_cast<long long>(pairs.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count(o.threads))
  for (long long kk = 0; kk < n; ++kk) {
    const auto [a, b] = pairs[static_cast<std::size_t>(kk)];
    const LinkSurface &A = *surface[a], &B = *surface[b];
    for (const Poses& X : poses) {
      const double apart = (X[a] * A.ball.center - X[b] * B.ball.center).norm();
      if (apart > A.ball.radius + B.ball.radius + o.band) continue;
      for (int side = 0; side < 2; ++side) {
        const Points p = side == 0 ? near_points(A, B, X[a], X[b], o.band)
                                   : near_points(B, A, X[b], X[a], o.band);
        Points& into = found[static_cast<std::size_t>(kk)][static_cast<std::size_t>(side)];
        into.insert(into.end(), p.begin(), p.end());
      }
    }
  }
  std::vector<Points> region(solids.size());
  for (std::size_t k = 0; k < pairs.size(); ++k)
    for (int side = 0; side < 2; ++side) {
      Points& into = region[side == 0 ? pairs[k].first : pairs[k].second];
      into.insert(into.end(), found[k][static_cast<std::size_t>(side)].begin(),
                  found[k][static_cast<std::size_t>(side)].end());
    }
  std::map<std::string, ProtrusionWeights> out;
  const auto least = static_cast<std::size_t>(
      std::max(1.0, std::ceil(o.min_share * static_cast<double>(o.samples))));
  for (std::size_t i = 0; i < region.size(); ++i) {
    Points kept = frequent(region[i], 0.5 * o.band, least);
    if (!kept.empty()) out[model.links[i].name] = {std::move(kept), 0.5 * o.band, o.weight};
  }
  return out;
}

RobotBakeResult rebake_contact_aware(const UrdfRobot& robot, const std::vector<LinkSolid>& solids,
                                     const RobotBakeOptions& bake, const RobotBakeResult& first,
                                     formats::SphereChoice choice, const PlannerRequest& planner,
                                     const ContactOptions& contact) {
  validate(contact);
  const PlannerSetup setup = make_planner_setup(first.model, solids, choice, planner);
  if (!setup.self_collision) return first;
  std::map<std::string, double> locked;
  for (const std::string& j : setup.locked_joints) locked[j] = setup.default_positions.at(j);
  RobotBakeOptions again = bake;
  again.outer_weights =
      contact_regions(first.model, solids, *setup.self_collision, locked, contact);
  return bake_robot(robot, solids, again);
}

}  // namespace medspheres
