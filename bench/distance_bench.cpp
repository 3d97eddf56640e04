// Distance queries between two copies of a mesh (paper Table 2), in one process, on the
// same seeded sequence of poses:
//   (a) FCL's exact mesh-mesh distance, BVHModel<OBBRSS> and BVHModel<RSS>;
//   (b) the baked sphere set, RSS tree (medspheres::fcl::distance on SphereSetGeometry);
//   (c) the same sphere set, ball tree;
//   (d) the same spheres as individual fcl::Sphere objects in two
//       fcl::DynamicAABBTreeCollisionManagerd, queried manager against manager with FCL's
//       default distance callback -- what robotics code does today. A query includes
//       moving both sets' objects and updating the managers, as a robot must.
//
// Usage: bench_distance [--poses N] [--meshes DIR] [--only SUBSTRING] [--max-spheres M]
//                       [--leaf L]
//   --poses N        poses per mesh (default 200)
//   --meshes DIR     folder with MANIFEST.tsv (default ../shared/meshes next to the source
//                    tree); without it, generated meshes are used
//   --only S         only meshes whose name contains S
//   --max-spheres M  bake at the largest resolution giving at most M spheres (default 800)
//   --leaf L         max_leaf_size of the sphere trees (default: SphereTreeOptions's)
//
// Poses: A and B are two copies of the mesh, each turned by a random rotation about its
// bounding-box centre; B is then moved along a random direction until FCL's exact
// distance equals the target gap, the gaps running evenly from 0 (touching, to 1e-4 of
// the box's largest side L) to L, shuffled. Times: each pose is run 5 times per method and
// the fastest run counts; the table gives the median and 95th percentile over the poses.
// Visits: node-pair bounds plus leaf tests per query for (a), (b), (c); for (d), the
// sphere pairs its callback tested (the managers' AABB tests are not counted). Error:
// (sphere distance - exact mesh distance) / L, in percent; the baker puts every sphere
// inside the solid, so it is not expected to be negative.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <fcl/fcl.h>

#include "bench_args.h"
#include "bench_timing.h"
#include "bench_util.h"
#include "medspheres/bake/bake.h"
#include "medspheres/fcl/sphere_set_geometry.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "support/shared_meshes.h"

namespace {

using medspheres::SphereSet;
using medspheres::TriangleMesh;
using medspheres::bench::Clock;
using medspheres::bench::make_bvh;
using medspheres::bench::percentile;

struct Workload {
  std::string name;
  TriangleMesh mesh;
};

// Closed "classic" meshes of MANIFEST.tsv spanning about 1k to 100k triangles.
std::vector<Workload> shared_workloads(const std::string& dir, const std::string& only) {
  const std::vector<std::string> wanted = {
      "libigl/decimated-knight.off", "odedstein/spot_low_resolution.obj",
      "asteroid/castalia.obj",       "cgal/knot1.off",
      "odedstein/bunny.obj",         "common3d/rocker-arm.obj",
      "odedstein/spot.obj",          "odedstein/armadillo.obj",
      "quartet/dragon.obj"};
  std::vector<std::string> present;
  for (const medspheres::test::SharedMesh& m : medspheres::test::read_manifest(dir))
    if (m.closed && m.classic()) present.push_back(m.file);
  std::vector<Workload> out;
  for (const std::string& file : wanted) {
    if (std::find(present.begin(), present.end(), file) == present.end()) continue;
    if (!only.empty() && file.find(only) == std::string::npos) continue;
    out.push_back({file, medspheres::load_mesh(dir + "/" + file).mesh});
  }
  return out;
}

std::vector<Workload> generated_workloads(const std::string& only) {
  std::vector<Workload> out;
  const auto add = [&](const std::string& name, TriangleMesh mesh) {
    if (only.empty() || name.find(only) != std::string::npos)
      out.push_back({name, std::move(mesh)});
  };
  add("generated torus 2k", medspheres::make_torus(1.0, 0.35, 40, 25));
  add("generated capsule 8k", medspheres::make_capsule(0.4, 1.0, 64, 32));
  add("generated torus 32k", medspheres::make_torus(1.0, 0.25, 200, 80));
  add("generated icosphere 82k", medspheres::make_icosphere(1.0, 6));
  return out;
}

struct Pose {
  fcl::Transform3d X_WA, X_WB;
  double exact = 0.0;  // FCL OBBRSS mesh distance
};

double mesh_distance(const fcl::BVHModel<fcl::OBBRSSd>& m, const fcl::Transform3d& X_WA,
                     const fcl::Transform3d& X_WB) {
  fcl::DistanceRequestd req;
  fcl::DistanceResultd res;
  return fcl::distance(&m, X_WA, &m, X_WB, req, res);
}

std::vector<Pose> make_poses(const TriangleMesh& mesh, const fcl::BVHModel<fcl::OBBRSSd>& model,
                             int count, unsigned seed) {
  const Eigen::AlignedBox3d box = mesh.bounds();
  const double L = box.sizes().maxCoeff();
  const Eigen::Vector3d mid = box.center();
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const auto rotation = [&] {
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    return q.normalized().toRotationMatrix();
  };
  std::vector<double> gaps(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k)
    gaps[static_cast<std::size_t>(k)] = L * k / std::max(1, count - 1);
  std::shuffle(gaps.begin(), gaps.end(), rng);
  std::vector<Pose> poses;
  for (double gap : gaps) {
    Pose p;
    p.X_WA = fcl::Transform3d::Identity();
    p.X_WA.linear() = rotation();
    p.X_WA.translation() = -(p.X_WA.linear() * mid);
    p.X_WB = fcl::Transform3d::Identity();
    p.X_WB.linear() = rotation();
    Eigen::Vector3d u(g(rng), g(rng), g(rng));
    u.normalize();
    // Distance is 1-Lipschitz in the translation: stepping back by (distance - gap)
    // never crosses the gap, and converges to it.
    double t = 2.0 * box.sizes().norm() + gap;
    const double target = std::max(gap, 1e-4 * L);
    for (int it = 0; it < 200; ++it) {
      p.X_WB.translation() = -(p.X_WB.linear() * mid) + t * u;
      const double d = mesh_distance(model, p.X_WA, p.X_WB);
      p.exact = d;
      if (d - target <= 1e-4 * L) break;
      t -= d - target;
    }
    poses.push_back(p);
  }
  return poses;
}

struct Result {
  std::string method;
  std::vector<double> micros;  // per pose
  std::vector<double> distance;
  double visits = 0.0;  // mean per query
};

// Times f(pose index) for every pose: five runs each, the fastest counts (the machine
// may be shared; the fastest run is the least disturbed).
template <class F>
std::vector<double> time_poses(std::size_t n, F&& f) {
  std::vector<double> best(n, 1e300);
  for (int round = 0; round < 5; ++round) {
    for (std::size_t k = 0; k < n; ++k) {
      const Clock::time_point t0 = Clock::now();
      f(k);
      best[k] = std::min(best[k], medspheres::bench::micros_since(t0));
    }
  }
  return best;
}

template <class BV, class Node>
Result run_fcl_mesh(const char* name, const TriangleMesh& mesh, const std::vector<Pose>& poses) {
  const auto model = make_bvh<BV>(mesh);
  Result r;
  r.method = name;
  // Statistics pass: FCL's own traversal, as fcl::distance sets it up.
  double visits = 0.0;
  for (const Pose& p : poses) {
    fcl::DistanceRequestd req(true);
    fcl::DistanceResultd res;
    Node node;
    fcl::detail::initialize(node, *model, p.X_WA, *model, p.X_WB, req, res);
    node.enable_statistics = true;
    fcl::detail::distance(&node);
    visits += node.num_bv_tests + node.num_leaf_tests;
    r.distance.push_back(res.min_distance);
  }
  r.visits = visits / poses.size();
  r.micros = time_poses(poses.size(), [&](std::size_t k) {
    fcl::DistanceRequestd req(true);
    fcl::DistanceResultd res;
    fcl::distance(model.get(), poses[k].X_WA, model.get(), poses[k].X_WB, req, res);
  });
  return r;
}

Result run_sphere_tree(const char* name, const SphereSet& spheres,
                       const medspheres::SphereTreeOptions& options, const std::vector<Pose>& poses,
                       medspheres::SphereTreeStats& stats) {
  const auto g = std::make_shared<medspheres::fcl::SphereSetGeometry>(spheres, options);
  stats = g->tree().stats();
  Result r;
  r.method = name;
  double visits = 0.0;
  for (const Pose& p : poses) {
    // Statistics pass through the runtime query the adapter runs.
    const medspheres::TreeDistance d = medspheres::distance(g->tree(), p.X_WA, g->tree(), p.X_WB);
    visits += static_cast<double>(d.stats.bv_tests + d.stats.leaf_tests);
    fcl::DistanceRequestd req(true);
    fcl::DistanceResultd res;
    r.distance.push_back(medspheres::fcl::distance(g.get(), p.X_WA, g.get(), p.X_WB, req, res));
  }
  r.visits = visits / poses.size();
  r.micros = time_poses(poses.size(), [&](std::size_t k) {
    fcl::DistanceRequestd req(true);
    fcl::DistanceResultd res;
    medspheres::fcl::distance(g.get(), poses[k].X_WA, g.get(), poses[k].X_WB, req, res);
  });
  return r;
}

// FCL's default distance callback, counting the pairs it is handed.
struct CountingDistanceData {
  fcl::DefaultDistanceData<double> data;
  std::size_t pairs = 0;
};

bool counting_distance(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data,
                       double& dist) {
  auto* d = static_cast<CountingDistanceData*>(data);
  ++d->pairs;
  return fcl::DefaultDistanceFunction(o1, o2, &d->data, dist);
}

Result run_managers(const SphereSet& spheres, const std::vector<Pose>& poses) {
  std::vector<std::shared_ptr<fcl::Sphered>> shapes;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects_a, objects_b;
  for (const medspheres::Sphere& s : spheres.spheres) {
    shapes.push_back(std::make_shared<fcl::Sphered>(s.radius));
    objects_a.push_back(std::make_unique<fcl::CollisionObjectd>(shapes.back()));
    objects_b.push_back(std::make_unique<fcl::CollisionObjectd>(shapes.back()));
  }
  fcl::DynamicAABBTreeCollisionManagerd manager_a, manager_b;
  for (auto& o : objects_a) manager_a.registerObject(o.get());
  for (auto& o : objects_b) manager_b.registerObject(o.get());
  manager_a.setup();
  manager_b.setup();
  const auto query = [&](const Pose& p, std::size_t* pairs) {
    for (std::size_t i = 0; i < spheres.size(); ++i) {
      objects_a[i]->setTransform(p.X_WA.linear(), p.X_WA * spheres.spheres[i].center);
      objects_a[i]->computeAABB();
      objects_b[i]->setTransform(p.X_WB.linear(), p.X_WB * spheres.spheres[i].center);
      objects_b[i]->computeAABB();
    }
    manager_a.update();
    manager_b.update();
    CountingDistanceData data;
    data.data.request.enable_nearest_points = true;
    manager_a.distance(&manager_b, &data, counting_distance);
    if (pairs != nullptr) *pairs = data.pairs;
    return data.data.result.min_distance;
  };
  Result r;
  r.method = "(d) fcl::Sphere x2 DynAABB";
  double visits = 0.0;
  for (const Pose& p : poses) {
    std::size_t pairs = 0;
    r.distance.push_back(query(p, &pairs));
    visits += static_cast<double>(pairs);
  }
  r.visits = visits / poses.size();
  r.micros = time_poses(poses.size(), [&](std::size_t k) { query(poses[k], nullptr); });
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  int num_poses = 200;
  std::size_t max_spheres = 800;
  int leaf = medspheres::SphereTreeOptions{}.max_leaf_size;
  std::string dir = medspheres::test::shared_meshes_dir(), only;
  medspheres::bench::Args args("bench_distance",
                               "Distance queries between two copies of a mesh (paper Table 2)");
  args.add("--poses", num_poses, "poses per mesh (at least 2 are run)");
  args.add_meshes(dir)->description(
      "folder with MANIFEST.tsv; empty: generated meshes instead of shared ones");
  args.add_only(only);
  args.add("--max-spheres", max_spheres,
           "bake at the largest resolution giving at most this many spheres");
  args.add("--leaf", leaf, "max_leaf_size of the sphere trees");
  args.parse(argc, argv);
  if (num_poses < 2) num_poses = 2;
  const std::vector<Workload> workloads =
      dir.empty() ? generated_workloads(only) : shared_workloads(dir, only);
  std::printf(
      "Distance between two copies of a mesh: %d poses per mesh, gaps 0..L (L = largest\n"
      "bounding-box side), sphere sets baked with at most %zu spheres, leaf size %d.\n"
      "Times in microseconds per query (fastest of 5 runs per pose; median and p95 over\n"
      "poses); visits per query; speedup = method's median / (b)'s median; error =\n"
      "(sphere distance - exact mesh distance) / L in %%.\n\n",
      num_poses, max_spheres, leaf);
  std::printf("%-34s %7s %7s  %-30s %10s %10s %9s %9s %9s %9s\n", "mesh", "tris", "spheres",
              "method", "median_us", "p95_us", "visits", "speedup", "err_mean%", "err_max%");

  struct Check {
    std::string text;
    bool ok;
  };
  std::vector<Check> checks;
  for (const Workload& w : workloads) {
    const auto obbrss = make_bvh<fcl::OBBRSSd>(w.mesh);
    const std::vector<Pose> poses = make_poses(w.mesh, *obbrss, num_poses, 12345u);
    const medspheres::MeshQuery query(w.mesh);
    const medspheres::BakeResult baked = medspheres::bake_max_spheres(query, max_spheres);
    const SphereSet& spheres = baked.spheres;
    const double L = w.mesh.bounds().sizes().maxCoeff();

    medspheres::SphereTreeOptions rss_options, ball_options;
    rss_options.max_leaf_size = ball_options.max_leaf_size = leaf;
    ball_options.kind = medspheres::BoundingVolumeKind::ball;
    medspheres::SphereTreeStats rss_stats, ball_stats;
    std::vector<Result> results;
    results.push_back(
        run_fcl_mesh<fcl::OBBRSSd, fcl::detail::MeshDistanceTraversalNodeOBBRSS<double>>(
            "(a) FCL mesh BVHModel<OBBRSS>", w.mesh, poses));
    results.push_back(run_fcl_mesh<fcl::RSSd, fcl::detail::MeshDistanceTraversalNodeRSS<double>>(
        "(a) FCL mesh BVHModel<RSS>", w.mesh, poses));
    results.push_back(
        run_sphere_tree("(b) spheres, RSS tree", spheres, rss_options, poses, rss_stats));
    results.push_back(
        run_sphere_tree("(c) spheres, ball tree", spheres, ball_options, poses, ball_stats));
    results.push_back(run_managers(spheres, poses));

    const double b_median = percentile(results[2].micros, 0.5);
    for (std::size_t m = 0; m < results.size(); ++m) {
      const Result& r = results[m];
      const double median = percentile(r.micros, 0.5);
      char err_mean[32] = "-", err_max[32] = "-";
      if (m >= 2) {
        double sum = 0.0, worst = 0.0;
        for (std::size_t k = 0; k < poses.size(); ++k) {
          const double e = 100.0 * (r.distance[k] - results[0].distance[k]) / L;
          sum += e;
          worst = std::max(worst, e);
        }
        std::snprintf(err_mean, sizeof err_mean, "%.3f", sum / poses.size());
        std::snprintf(err_max, sizeof err_max, "%.3f", worst);
      }
      std::printf("%-34s %7s %7s  %-30s %10.2f %10.2f %9.1f %8.1fx %9s %9s\n",
                  m == 0 ? w.name.c_str() : "",
                  m == 0 ? std::to_string(w.mesh.num_triangles()).c_str() : "",
                  m == 0 ? std::to_string(spheres.size()).c_str() : "", r.method.c_str(), median,
                  percentile(r.micros, 0.95), r.visits, median / b_median, err_mean, err_max);
    }
    std::printf(
        "%-34s %7s %7s  trees: RSS depth %zu, leaves %zu (size %zu..%zu), nodes %zu, "
        "%zu bytes; ball depth %zu, nodes %zu, %zu bytes\n",
        "", "", "", rss_stats.depth, rss_stats.leaves, rss_stats.min_leaf_size,
        rss_stats.max_leaf_size, rss_stats.nodes, rss_stats.bytes, ball_stats.depth,
        ball_stats.nodes, ball_stats.bytes);
    // (b), (c) and (d) measure the same sphere sets: their distances must agree.
    double disagreement = 0.0;
    for (std::size_t k = 0; k < poses.size(); ++k) {
      disagreement =
          std::max(disagreement, std::abs(results[2].distance[k] - results[3].distance[k]));
      disagreement =
          std::max(disagreement, std::abs(results[2].distance[k] - results[4].distance[k]));
    }
    std::printf("%-34s %7s %7s  (b), (c), (d) distances agree to %.1e; bake resolution %d\n\n", "",
                "", "", disagreement, baked.stats.resolution);

    const double a_obbrss = percentile(results[0].micros, 0.5) / b_median;
    const double d_ratio = percentile(results[4].micros, 0.5) / b_median;
    const double c_ratio = percentile(results[3].micros, 0.5) / b_median;
    char text[256];
    if (w.mesh.num_triangles() >= 20000) {
      std::snprintf(text, sizeof text,
                    "%s: (b) vs (a) OBBRSS %.1fx (target >= 50x on >= 20k triangles)",
                    w.name.c_str(), a_obbrss);
      checks.push_back({text, a_obbrss >= 50.0});
    }
    std::snprintf(text, sizeof text, "%s: (b) vs (a) OBBRSS %.1fx (target >= 10x)", w.name.c_str(),
                  a_obbrss);
    checks.push_back({text, a_obbrss >= 10.0});
    std::snprintf(text, sizeof text, "%s: (b) vs (d) %.1fx (target >= 5x)", w.name.c_str(),
                  d_ratio);
    checks.push_back({text, d_ratio >= 5.0});
    std::snprintf(text, sizeof text, "%s: (c) / (b) %.2f (target: (b) no slower, >= 1)",
                  w.name.c_str(), c_ratio);
    checks.push_back({text, c_ratio >= 1.0});
    if (spheres.size() >= 300 && spheres.size() <= 800) {
      std::snprintf(text, sizeof text, "%s: (b) median %.2f us with %zu spheres (target <= 10 us)",
                    w.name.c_str(), b_median, spheres.size());
      checks.push_back({text, b_median <= 10.0});
    }
  }
  std::printf("Targets:\n");
  for (const Check& c : checks) std::printf("  %-4s %s\n", c.ok ? "ok" : "MISS", c.text.c_str());
  return 0;
}
