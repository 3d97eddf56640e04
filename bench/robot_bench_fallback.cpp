// bench_checker --fallback-report (robot_bench_fallback.h).

#include "robot_bench_fallback.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <fcl/narrowphase/distance.h>

#include "bench_timing.h"
#include "medspheres/fcl/scene_from_fcl.h"

namespace medspheres::bench {
namespace {

using check::Verdict;

struct PairTally {
  std::size_t undecided = 0;  // configurations in which the bounds left the pair open
  std::size_t trees_colliding = 0, trees_free = 0, meshes = 0, meshes_colliding = 0;
  double tree_micros = 0.0, mesh_micros = 0.0;
  std::size_t planes = 0;     // of the meshes' pairs, proved free by a separating plane
  double plane_micros = 0.0;  // the planes' search on every pair the trees left open
  std::size_t cells = 0;      // octree pairs also settled by OctreeCells
  double cells_micros = 0.0;
  std::vector<double> mesh_distance;  // settled pairs: FCL's distance (capped above margin)
};

std::string pair_name(const check::RobotChecker& c, const check::UndecidedPair& p) {
  return c.links()[p.link] + " / " +
         (p.self ? c.links()[p.other] : "scene " + std::to_string(p.other));
}

// FCL's distance between a link's mesh and a geometry, without the margin's pruning (-1
// without a mesh).
double true_distance(const fcl::BoundedGeometry& a, const ::fcl::Transform3d& X_WA,
                     const ::fcl::CollisionGeometryd* b, const ::fcl::Transform3d& X_WB) {
  if (a.mesh() == nullptr || b == nullptr) return -1.0;
  ::fcl::DistanceRequestd request;
  ::fcl::DistanceResultd result;
  return ::fcl::distance(a.mesh(), X_WA, b, X_WB, request, result);
}

// The per-pair table of the fallback report: the 30 pairs that cost the trees and the
// meshes most, first.
void print_pair_rows(const std::map<std::string, PairTally>& tally) {
  std::vector<std::pair<std::string, PairTally>> rows(tally.begin(), tally.end());
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
    return a.second.tree_micros + a.second.mesh_micros >
           b.second.tree_micros + b.second.mesh_micros;
  });
  std::printf("%-52s %6s %6s %6s %6s %6s %6s %9s %9s %9s %9s %8s %8s\n", "pair", "open", "tr/hit",
              "tr/free", "mesh", "m/hit", "plane", "tree us", "mesh us", "plane us", "cells us",
              "free d10", "free d50");
  for (std::size_t k = 0; k < rows.size() && k < 30; ++k) {
    PairTally& s = rows[k].second;
    std::sort(s.mesh_distance.begin(), s.mesh_distance.end());
    auto pct = [&](double f) {
      return s.mesh_distance.empty()
                 ? -1.0
                 : s.mesh_distance[std::size_t(f * double(s.mesh_distance.size() - 1))];
    };
    std::printf(
        "%-52s %6zu %6zu %6zu %6zu %6zu %6zu %9.1f %9.1f %9.1f %9s %8.4f %8.4f\n",
        rows[k].first.c_str(), s.undecided, s.trees_colliding, s.trees_free, s.meshes,
        s.meshes_colliding, s.planes, s.undecided ? s.tree_micros / double(s.undecided) : 0.0,
        s.meshes ? s.mesh_micros / double(s.meshes) : 0.0,
        s.meshes ? s.plane_micros / double(s.meshes) : 0.0,
        s.cells ? std::to_string(s.cells_micros / double(s.cells)).substr(0, 7).c_str() : "-",
        pct(0.1), pct(0.5));
  }
  std::printf("(%zu pairs in all)\n", rows.size());
}

}  // namespace

void print_fallback_report(const CheckerBenchInput& in, const fcl::CertifiedChecker& certified) {
  const check::RobotChecker& c = certified.spheres();
  const fcl::RobotBounds& rb = certified.fallback();
  const std::size_t n = in.configs.size();
  std::vector<double> q;
  for (const Eigen::VectorXd& x : in.configs) q.insert(q.end(), x.data(), x.data() + x.size());
  std::vector<Verdict> v(n);
  c.check(q.data(), n, check::Mode::bounds, v.data(), 1);
  // geometry index of each checker link
  std::vector<std::size_t> geo;
  for (const std::string& l : c.links()) {
    std::size_t g = 0;
    while (rb.geometries()[g].link() != l) ++g;
    geo.push_back(g);
  }
  // The checker's scene objects (UndecidedPair::other) as indices in in.scene.
  const std::vector<std::size_t> source = fcl::scene_from_fcl(in.scene).source;
  // The checker's octree path (OctreeCells) beside FCL's own octree query.
  std::vector<std::unique_ptr<const fcl::OctreeCells>> cells;
  for (const ::fcl::CollisionObjectd* o : in.scene)
    cells.push_back(fcl::octree_cells_of(*o->collisionGeometry(), o->getTransform()));
  std::vector<std::unique_ptr<const fcl::OctreeCells::Link>> cell_links;
  for (const fcl::BoundedGeometry& g : rb.geometries())
    cell_links.push_back(g.mesh() ? std::make_unique<const fcl::OctreeCells::Link>(g) : nullptr);
  std::size_t cells_disagree = 0, planes_disagree = 0;
  std::map<std::string, PairTally> tally;
  double t_bounds = 0, t_poses = 0, t_trees = 0, t_meshes = 0;
  std::size_t configs = 0, pairs_total = 0, truth_colliding = 0, decided_by_trees = 0,
              to_meshes = 0;
  std::vector<std::size_t> pairs_per_config;
  const double margin = in.margin;
  for (std::size_t i = 0; i < n; ++i) {
    if (v[i] != Verdict::undecided) continue;
    ++configs;
    truth_colliding += in.reference[i];
    std::vector<check::UndecidedPair> pairs;
    double t = thread_cpu_micros();
    c.check(q.data() + i * c.num_positions(), check::Mode::bounds, &pairs);
    t_bounds += thread_cpu_micros() - t;
    pairs_per_config.push_back(pairs.size());
    pairs_total += pairs.size();
    t = thread_cpu_micros();
    const auto X = rb.poses(in.configs[i], c.options().X_WB);
    t_poses += thread_cpu_micros() - t;
    // Every pair, without stopping early: what the trees and the meshes say of each.
    bool trees_hit = false, any_open = false;
    for (const check::UndecidedPair& p : pairs) {
      PairTally& s = tally[pair_name(c, p)];
      ++s.undecided;
      const std::size_t a = geo[p.link];
      const std::size_t object = p.self ? 0 : source[p.other];  // index in in.scene
      const ::fcl::CollisionObjectd* o = p.self ? nullptr : in.scene[object];
      t = thread_cpu_micros();
      const fcl::CollideResult r =
          p.self ? fcl::decide(rb.geometries()[a], X[a], rb.geometries()[geo[p.other]],
                               X[geo[p.other]], margin)
                 : fcl::decide(rb.geometries()[a], X[a], *o->collisionGeometry(), o->getTransform(),
                               margin);
      const double dt = thread_cpu_micros() - t;
      s.tree_micros += dt;
      if (!trees_hit) t_trees += dt;
      if (r.verdict == BoundsVerdict::colliding) {
        ++s.trees_colliding;
        trees_hit = true;
        continue;
      }
      if (r.verdict == BoundsVerdict::free) {
        ++s.trees_free;
        continue;
      }
      t = thread_cpu_micros();
      const bool plane = certified.plane_free(p, X, r);
      s.plane_micros += thread_cpu_micros() - t;
      s.planes += plane;
      t = thread_cpu_micros();
      const fcl::CollideResult m =
          p.self ? fcl::settle(r, rb.geometries()[a], X[a], rb.geometries()[geo[p.other]],
                               X[geo[p.other]], margin)
                 : fcl::settle(r, rb.geometries()[a], X[a], *o->collisionGeometry(),
                               o->getTransform(), margin);
      const double dm = thread_cpu_micros() - t;
      ++s.meshes;
      s.mesh_micros += dm;
      s.meshes_colliding += m.verdict == BoundsVerdict::colliding;
      planes_disagree += plane && m.verdict != BoundsVerdict::free;
      if (!p.self && cells[object] && cell_links[a]) {
        t = thread_cpu_micros();
        const bool hit = cells[object]->distance(*cell_links[a], X[a], margin) <= margin;
        s.cells_micros += thread_cpu_micros() - t;
        ++s.cells;
        cells_disagree += hit != (m.verdict == BoundsVerdict::colliding);
      }
      if (m.verdict == BoundsVerdict::free)
        s.mesh_distance.push_back(true_distance(
            rb.geometries()[a], X[a],
            p.self ? rb.geometries()[geo[p.other]].mesh() : o->collisionGeometry().get(),
            p.self ? X[geo[p.other]] : o->getTransform()));
      any_open = true;
      if (!trees_hit) t_meshes += dm;  // an upper bound of what the checker spends
    }
    decided_by_trees += trees_hit || !any_open;
    to_meshes += !trees_hit && any_open;
  }
  std::sort(pairs_per_config.begin(), pairs_per_config.end());
  std::printf(
      "\nfallback report: %zu configurations undecided by the bounds (%zu colliding by the "
      "reference), %zu undecided pairs (median %zu, max %zu per configuration); %zu settled by "
      "the sphere trees alone, %zu need a mesh\n",
      configs, truth_colliding, pairs_total,
      pairs_per_config.empty() ? 0 : pairs_per_config[pairs_per_config.size() / 2],
      pairs_per_config.empty() ? 0 : pairs_per_config.back(), decided_by_trees, to_meshes);
  std::printf(
      "octree pairs: FCL's octree query and OctreeCells disagree in %zu (the mesh us column is "
      "FCL's; cells us: OctreeCells on the same pairs)\n",
      cells_disagree);
  std::printf(
      "separating planes: %zu of the meshes' pairs proved free by a plane where the meshes "
      "did not find them free (plane: the pairs a plane proved free; plane us: its search, per "
      "pair the trees left open)\n",
      planes_disagree);
  const double per = configs ? 1.0 / double(configs) : 0.0;
  std::printf(
      "per undecided configuration (us, thread CPU): bounds again %.1f, poses %.1f, sphere trees "
      "%.1f (up to the first colliding pair), meshes <= %.1f\n",
      t_bounds * per, t_poses * per, t_trees * per, t_meshes * per);
  print_pair_rows(tally);
}

}  // namespace medspheres::bench
