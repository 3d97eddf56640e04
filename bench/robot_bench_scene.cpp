// bench_robot's seeded scene (robot_bench_scene.h).

#include "robot_bench_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include <fcl/fcl.h>
#include <octomap/octomap.h>

#include "bench_util.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"

namespace medspheres::bench {
namespace {

// Closed classic meshes of a few thousand triangles from ../shared/meshes.
const char* const kSharedMeshes[] = {"odedstein/spot_low_resolution.obj",
                                     "libigl/decimated-knight.off",
                                     "odedstein/fish_low_resolution.obj", "odedstein/bunny.obj"};

using Rng = std::mt19937;

double uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

::fcl::Transform3d at(const Eigen::Vector3d& p) {
  ::fcl::Transform3d X = ::fcl::Transform3d::Identity();
  X.translation() = p;
  return X;
}

class Builder {
 public:
  Builder(BenchScene& scene, double scale) : scene_(scene), s_(scale) {}

  void box(const std::string& name, const Eigen::Vector3d& size, const Eigen::Vector3d& centre) {
    add(name, std::make_shared<::fcl::Boxd>(s_ * size), at(s_ * centre));
    ++scene_.boxes;
  }

  // The mesh turned by a seeded rotation about its box centre, scaled to the diagonal
  // `diagonal`, its box centre above `base` and its lowest point at base's height.
  void mesh(const std::string& name, TriangleMesh m, Rng& rng, double diagonal,
            const Eigen::Vector3d& base) {
    Eigen::AlignedBox3d box;
    for (const auto& v : m.vertices) box.extend(v);
    const double k = s_ * diagonal / box.diagonal().norm();
    Eigen::Matrix3d R = Eigen::Quaterniond(uniform(rng, -1, 1), uniform(rng, -1, 1),
                                           uniform(rng, -1, 1), uniform(rng, -1, 1))
                            .normalized()
                            .toRotationMatrix();
    for (auto& v : m.vertices) v = k * (R * (v - box.center()));
    double low = 0.0;
    for (const auto& v : m.vertices) low = std::min(low, v.z());
    scene_.mesh_triangles += m.triangles.size();
    ++scene_.meshes;
    auto bvh = make_bvh<::fcl::OBBRSSd>(m);
    scene_.solids[bvh.get()] = std::make_shared<MeshQuery>(m);
    add(name, std::move(bvh), at(s_ * base - Eigen::Vector3d(0, 0, low)));
  }

  void octree(const std::shared_ptr<octomap::OcTree>& tree) {
    add("octomap", std::make_shared<::fcl::OcTreed>(tree), ::fcl::Transform3d::Identity());
  }

 private:
  void add(const std::string& name, std::shared_ptr<::fcl::CollisionGeometryd> g,
           const ::fcl::Transform3d& X) {
    auto o = std::make_shared<::fcl::CollisionObjectd>(std::move(g), X);
    o->computeAABB();
    scene_.objects.push_back({name, std::move(o)});
  }

  BenchScene& scene_;
  double s_;
};

void table(Builder& b) {
  b.box("table top", {0.7, 1.2, 0.04}, {0.7, 0.0, -0.02});
  for (double x : {0.38, 1.02})
    for (double y : {-0.57, 0.57}) b.box("table leg", {0.04, 0.04, 0.76}, {x, y, -0.42});
}

// A shelf unit to the left: four boards, two sides, two or three boxes on each board.
void shelves(Builder& b, Rng& rng) {
  const double y = 0.75, depth = 0.3;
  for (double z : {-0.6, -0.2, 0.2, 0.6}) {
    b.box("shelf board", {0.9, depth, 0.02}, {0.2, y, z});
    double x = -0.22;
    while (true) {
      const Eigen::Vector3d size(uniform(rng, 0.05, 0.15), uniform(rng, 0.05, 0.2),
                                 uniform(rng, 0.05, 0.25));
      x += size.x() / 2 + uniform(rng, 0.02, 0.1);
      if (x + size.x() / 2 > 0.62) break;
      b.box("shelf box", size, {x, y + uniform(rng, -0.05, 0.05), z + 0.01 + size.z() / 2});
      x += size.x() / 2;
    }
  }
  for (double x : {-0.26, 0.66}) b.box("shelf side", {0.02, depth, 1.44}, {x, y, 0.0});
}

std::vector<TriangleMesh> scene_meshes(const std::string& dir) {
  std::vector<TriangleMesh> out;
  for (const char* file : kSharedMeshes) {
    const std::filesystem::path p = std::filesystem::path(dir) / file;
    if (!dir.empty() && std::filesystem::exists(p)) out.push_back(load_mesh(p.string()).mesh);
  }
  if (out.empty()) {
    out.push_back(make_torus(0.3, 0.1, 32, 16));
    out.push_back(make_icosphere(0.3, 3));
    out.push_back(make_capsule(0.1, 0.3, 24, 8));
  }
  return out;
}

// The cloud: a wall at y = -0.8 and a pile of clutter (noisy spheres) in front of it.
std::shared_ptr<octomap::OcTree> cloud_octree(Rng& rng, double scale, double resolution,
                                              std::size_t& points) {
  auto tree = std::make_shared<octomap::OcTree>(scale * resolution);
  auto add = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = scale * p;
    tree->updateNode(octomap::point3d(float(q.x()), float(q.y()), float(q.z())), true);
    ++points;
  };
  for (int k = 0; k < 6000; ++k)
    add({uniform(rng, -0.4, 0.8), -0.8 + uniform(rng, -0.01, 0.01), uniform(rng, -0.8, 0.8)});
  for (int blob = 0; blob < 5; ++blob) {
    const Eigen::Vector3d c(uniform(rng, -0.2, 0.6), uniform(rng, -0.7, -0.55),
                            uniform(rng, -0.6, 0.4));
    const double r = uniform(rng, 0.05, 0.12);
    for (int k = 0; k < 800; ++k) {
      const Eigen::Vector3d d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      if (d.norm() > 1e-3) add(c + (r + uniform(rng, -0.005, 0.005)) * d.normalized());
    }
  }
  tree->updateInnerOccupancy();
  return tree;
}

// Every leaf cell FCL counts as occupied (fcl::OcTree::isNodeOccupied: log-odds at or above
// the tree's occupancy threshold), as a box of 12 triangles, in one mesh.
std::shared_ptr<::fcl::CollisionObjectd> cells_mesh(const std::shared_ptr<octomap::OcTree>& tree,
                                                    BenchScene& scene) {
  std::size_t& cells = scene.octree_cells;
  const ::fcl::OcTreed fcl_view(tree);
  TriangleMesh all;
  for (auto it = tree->begin_leafs(); it != tree->end_leafs(); ++it) {
    if (!fcl_view.isNodeOccupied(&*it)) continue;
    ++cells;
    const double h = it.getSize() / 2;
    TriangleMesh box = make_box(Eigen::Vector3d(h, h, h), 1);
    const int base = static_cast<int>(all.vertices.size());
    const Eigen::Vector3d c(it.getX(), it.getY(), it.getZ());
    for (const auto& v : box.vertices) all.vertices.push_back(c + v);
    for (const auto& t : box.triangles)
      all.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  }
  auto bvh = make_bvh<::fcl::OBBRSSd>(all);
  scene.solids[bvh.get()] = std::make_shared<MeshQuery>(all);
  auto o = std::make_shared<::fcl::CollisionObjectd>(std::move(bvh));
  o->computeAABB();
  return o;
}

}  // namespace

std::vector<const ::fcl::CollisionObjectd*> BenchScene::pointers(bool cells_as_mesh) const {
  std::vector<const ::fcl::CollisionObjectd*> out;
  for (const SceneObject& o : objects)
    out.push_back(cells_as_mesh && o.name == "octomap" ? octree_cells_mesh.get() : o.object.get());
  return out;
}

BenchScene make_scene(unsigned seed, const std::string& meshes_dir, double scale) {
  BenchScene scene;
  Rng rng(seed);
  Builder b(scene, scale);
  table(b);
  shelves(b, rng);
  const std::vector<TriangleMesh> meshes = scene_meshes(meshes_dir);
  const Eigen::Vector3d bases[] = {
      {0.55, -0.3, 0.0}, {0.75, 0.25, 0.0}, {0.1, 0.75, 0.21}, {-0.55, 0.0, 0.2}};
  for (std::size_t k = 0; k < meshes.size() && k < 4; ++k)
    b.mesh("mesh " + std::to_string(k), meshes[k], rng, uniform(rng, 0.2, 0.3), bases[k]);
  scene.octree_resolution = scale * 0.03;
  const auto tree = cloud_octree(rng, scale, 0.03, scene.cloud_points);
  b.octree(tree);
  scene.octree_cells_mesh = cells_mesh(tree, scene);
  return scene;
}

}  // namespace medspheres::bench
