// Why there are two triangle hierarchies: closest-point queries by MeshQuery (a 4-wide
// hierarchy of float boxes, built by the surface-area heuristic, in the mesh target) and
// by TriangleTree (the runtime's binary RSS hierarchy, through the sphere-tree traversal,
// as a one-ball sphere tree of radius 1e-300 moved to each point), on the same points.
// Both end in the same point-triangle kernel, so their distances must agree to the bit;
// the table says how often they do not (column "differ").
//
// No options: the generated 100k-triangle torus, the bundled examples and, when
// ../shared/meshes is there, its closed meshes; 5000 interior and 5000 near-surface
// points each (as bench_mesh_query draws them). Each timing is the median of 3
// interleaved rounds, in CPU time of the calling thread, so that other processes on a
// busy machine do not count.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>
#include <utility>
#include <vector>

#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_tree.h"
#include "medspheres/triangle_tree.h"
#include "support/random_points.h"
#include "support/shared_meshes.h"

namespace {

using medspheres::TriangleMesh;
using Points = std::vector<Eigen::Vector3d>;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Timing {
  double mesh_query_qps = 0.0, tree_qps = 0.0;
  double tree_tests = 0.0;  // node bounds and leaf tests per query
  std::size_t differ = 0;
};

Timing measure(const medspheres::MeshQuery& q, const medspheres::TriangleTree& tree,
               const Points& pts) {
  medspheres::SphereSet one;
  one.spheres.push_back({Eigen::Vector3d::Zero(), 1e-300});
  const medspheres::SphereTree ball(one);
  std::vector<double> by_query(pts.size()), by_tree(pts.size()), t_query, t_tree;
  std::uint64_t tests = 0;
  for (int round = 0; round < 3; ++round) {
    double t0 = cpu_seconds();
    for (std::size_t i = 0; i < pts.size(); ++i) by_query[i] = q.closest_point(pts[i]).distance();
    t_query.push_back(cpu_seconds() - t0);
    tests = 0;
    t0 = cpu_seconds();
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Isometry3d X_WA{Eigen::Translation3d(pts[i])};
      const medspheres::TreeDistance d =
          medspheres::distance(ball, X_WA, tree, Eigen::Isometry3d::Identity());
      by_tree[i] = d.distance;
      tests += d.stats.bv_tests + d.stats.leaf_tests;
    }
    t_tree.push_back(cpu_seconds() - t0);
  }
  std::sort(t_query.begin(), t_query.end());
  std::sort(t_tree.begin(), t_tree.end());
  const double n = static_cast<double>(pts.size());
  Timing out;
  out.mesh_query_qps = n / t_query[1];
  out.tree_qps = n / t_tree[1];
  out.tree_tests = static_cast<double>(tests) / n;
  for (std::size_t i = 0; i < pts.size(); ++i) out.differ += by_query[i] != by_tree[i];
  return out;
}

}  // namespace

int main() {
  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  meshes.emplace_back("torus-100k (generated)", medspheres::make_torus(1.0, 0.4, 250, 200));
  for (const char* f : {"knot1.off", "eight.off"}) {
    const std::string path = std::string(MEDSPHERES_SOURCE_DIR) + "/examples/data/" + f;
    meshes.emplace_back(std::string("examples/") + f, medspheres::load_mesh(path).mesh);
  }
  for (const medspheres::test::SharedMesh& m : medspheres::test::shared_meshes())
    if (m.closed) meshes.emplace_back(m.file, medspheres::load_mesh(m.path).mesh);

  std::printf("Closest points: MeshQuery (4-wide float AABB) vs TriangleTree (binary RSS)\n");
  std::printf(
      "q/s: queries per CPU second, one thread; tests: TriangleTree bounds + leaves per query\n\n");
  std::printf("%-30s %8s %-8s %11s %11s %6s %8s %6s\n", "mesh", "tris", "kind", "MeshQuery",
              "TriangleTree", "ratio", "tests", "differ");
  std::vector<double> ratios;
  for (const auto& [name, mesh] : meshes) {
    const medspheres::MeshQuery q(mesh);
    const medspheres::TriangleTree tree(mesh);
    const Points interior = medspheres::test::points_inside(
        mesh.bounds(), 5000, 1, [&q](const Eigen::Vector3d& p) { return q.inside(p); });
    const Points near =
        medspheres::test::near_surface_points(mesh, 5000, 2, 1e-3 * mesh.bounds().sizes().norm());
    for (const auto& [kind, pts] :
         {std::make_pair("interior", &interior), std::make_pair("near", &near)}) {
      if (pts->empty()) continue;
      const Timing t = measure(q, tree, *pts);
      ratios.push_back(t.mesh_query_qps / t.tree_qps);
      std::printf("%-30s %8zu %-8s %11.0f %11.0f %6.2f %8.1f %6zu\n", name.c_str(),
                  mesh.triangles.size(), kind, t.mesh_query_qps, t.tree_qps, ratios.back(),
                  t.tree_tests, t.differ);
      std::fflush(stdout);
    }
  }
  std::sort(ratios.begin(), ratios.end());
  std::printf("\nMeshQuery / TriangleTree throughput: min %.2f, median %.2f, max %.2f\n",
              ratios.front(), ratios[ratios.size() / 2], ratios.back());
  return 0;
}
