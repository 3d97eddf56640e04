// Closest-point throughput of MeshQuery against CGAL's AABB_tree (with
// accelerate_distance_queries), on the same query points, side by side in one process.
//
// Usage: bench_mesh_query [--points N] [--meshes DIR] [--only SUBSTRING]
//   --points N   queries per kind and mesh (default 20000)
//   --meshes DIR folder with MANIFEST.tsv (default: ../shared/meshes next to the
//                source tree, when it exists); its closed meshes are measured too
//
// Query kinds: "interior" points drawn uniformly inside the solid (where baking spends
// its time) and "near" points within 0.1% of the bounding-box diagonal of the surface.
// Each timing is the median of 3 interleaved rounds (ours, CGAL, ours, CGAL, ...).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "bench_args.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "support/random_points.h"
#include "support/shared_meshes.h"

namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median3(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Workload {
  std::string name;
  medspheres::TriangleMesh mesh;
};

struct Row {
  std::string mesh, kind;
  std::size_t triangles = 0, points = 0;
  double ours_qps = 0, cgal_qps = 0, ours2_qps = 0;
  double nodes = 0, tris = 0;
  double max_diff = 0;
};

Row measure(const std::string& name, const std::string& kind, const medspheres::MeshQuery& q,
            const Tree& tree, const std::vector<Eigen::Vector3d>& pts) {
  Row r;
  r.mesh = name;
  r.kind = kind;
  r.triangles = q.mesh().triangles.size();
  r.points = pts.size();
  std::vector<double> ours(pts.size()), cgal(pts.size());
  std::vector<double> t_ours, t_cgal, t_two;
  medspheres::QueryCounters counters;
  for (int round = 0; round < 3; ++round) {
    medspheres::QueryCounters c;
    auto t0 = Clock::now();
    for (std::size_t i = 0; i < pts.size(); ++i)
      ours[i] = q.closest_point(pts[i], &c).squared_distance;
    t_ours.push_back(seconds_since(t0));
    counters = c;

    t0 = Clock::now();
    for (std::size_t i = 0; i < pts.size(); ++i)
      cgal[i] = tree.squared_distance(K::Point_3(pts[i].x(), pts[i].y(), pts[i].z()));
    t_cgal.push_back(seconds_since(t0));

    t0 = Clock::now();
    const std::vector<medspheres::ClosestPoint> two = q.closest_points(pts, 2);
    t_two.push_back(seconds_since(t0));
    if (two.size() != pts.size()) std::abort();
  }
  for (std::size_t i = 0; i < pts.size(); ++i)
    r.max_diff = std::max(r.max_diff, std::abs(std::sqrt(ours[i]) - std::sqrt(cgal[i])));
  const double n = static_cast<double>(pts.size());
  r.ours_qps = n / median3(t_ours);
  r.cgal_qps = n / median3(t_cgal);
  r.ours2_qps = n / median3(t_two);
  r.nodes = static_cast<double>(counters.nodes_visited) / n;
  r.tris = static_cast<double>(counters.triangles_tested) / n;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t npoints = 20000;
  std::string dir = medspheres::test::shared_meshes_dir(), only;
  medspheres::bench::Args args("bench_mesh_query",
                               "Closest-point throughput of MeshQuery against CGAL's AABB_tree");
  args.add("--points", npoints, "queries per kind and mesh");
  args.add_meshes(dir);
  args.add_only(only);
  args.parse(argc, argv);

  std::vector<Workload> work;
  work.push_back({"torus-100k (generated)", medspheres::make_torus(1.0, 0.4, 250, 200)});
  const std::string examples = std::string(MEDSPHERES_SOURCE_DIR) + "/examples/data/";
  for (const char* f : {"knot1.off", "eight.off"})
    work.push_back({std::string("examples/") + f, medspheres::load_mesh(examples + f).mesh});
  if (!dir.empty())
    for (const medspheres::test::SharedMesh& m : medspheres::test::read_manifest(dir))
      if (m.closed) work.push_back({m.file, medspheres::load_mesh(m.path).mesh});

  std::printf("MeshQuery vs CGAL AABB_tree (accelerate_distance_queries), %zu points per kind\n",
              npoints);
  std::printf(
      "q/s: queries per second; 1t: one thread; x2t: MeshQuery batch on 2 threads over 1t\n\n");
  std::printf("%-30s %8s %-8s %10s %10s %6s %10s %5s %7s %6s %6s %9s\n", "mesh", "tris", "kind",
              "ours q/s", "CGAL q/s", "ratio", "ours 2t", "x2t", "nodes", "tris", "depth",
              "max|dd|");
  std::vector<double> ratios;
  for (const Workload& w : work) {
    if (!only.empty() && w.name.find(only) == std::string::npos) continue;
    const medspheres::MeshQuery q(w.mesh);
    Triangles tris;
    tris.reserve(w.mesh.triangles.size());
    for (std::size_t t = 0; t < w.mesh.triangles.size(); ++t) {
      const auto& a = w.mesh.corner(t, 0);
      const auto& b = w.mesh.corner(t, 1);
      const auto& c = w.mesh.corner(t, 2);
      tris.emplace_back(K::Point_3(a.x(), a.y(), a.z()), K::Point_3(b.x(), b.y(), b.z()),
                        K::Point_3(c.x(), c.y(), c.z()));
    }
    Tree tree(tris.begin(), tris.end());
    tree.accelerate_distance_queries();
    tree.squared_distance(K::Point_3(0, 0, 0));  // force both lazy builds before timing

    const auto interior = medspheres::test::points_inside(
        w.mesh.bounds(), npoints, 1, [&q](const Eigen::Vector3d& p) { return q.inside(p); });
    const auto near = medspheres::test::near_surface_points(w.mesh, npoints, 2,
                                                            1e-3 * w.mesh.bounds().sizes().norm());
    for (const auto& [kind, pts] : {std::make_pair(std::string("interior"), interior),
                                    std::make_pair(std::string("near"), near)}) {
      if (pts.empty()) continue;
      const Row r = measure(w.name, kind, q, tree, pts);
      if (kind == "interior") ratios.push_back(r.ours_qps / r.cgal_qps);
      std::printf("%-30s %8zu %-8s %10.0f %10.0f %6.2f %10.0f %5.2f %7.1f %6.1f %6zu %9.1e\n",
                  r.mesh.c_str(), r.triangles, r.kind.c_str(), r.ours_qps, r.cgal_qps,
                  r.ours_qps / r.cgal_qps, r.ours2_qps, r.ours2_qps / r.ours_qps, r.nodes, r.tris,
                  q.stats().depth, r.max_diff);
      std::fflush(stdout);
    }
  }
  if (!ratios.empty()) {
    std::sort(ratios.begin(), ratios.end());
    std::printf(
        "\ninterior ratio ours/CGAL (1 thread): min %.2f, median %.2f, max %.2f; target >= 3\n",
        ratios.front(), ratios[ratios.size() / 2], ratios.back());
  }
  return 0;
}
