#include "medspheres/fcl/scene_from_fcl.h"

#include <map>
#include <stdexcept>
#include <string>

#include <fcl/fcl.h>

namespace medspheres::fcl {
namespace {

template <class BV>
bool add_bvh(const ::fcl::CollisionGeometryd& g, const Eigen::Isometry3d& X,
             const std::string& name, check::Scene& scene) {
  const auto* m = dynamic_cast<const ::fcl::BVHModel<BV>*>(&g);
  if (m == nullptr) return false;
  TriangleMesh mesh;
  for (int i = 0; i < m->num_vertices; ++i) mesh.vertices.push_back(m->vertices[i]);
  for (int i = 0; i < m->num_tris; ++i) {
    const ::fcl::Triangle& t = m->tri_indices[i];
    mesh.triangles.push_back({int(t[0]), int(t[1]), int(t[2])});
  }
  scene.add_mesh(mesh, X, name);
  return true;
}

void add_octree(const ::fcl::OcTreed& tree, const Eigen::Isometry3d& X, const std::string& name,
                check::Scene& scene) {
  const bool rotated = !X.linear().isIdentity(0.0);
  std::map<double, std::vector<Eigen::Vector3d>> by_side;
  for (const std::array<double, 6>& b : tree.toBoxes()) {
    const Eigen::Vector3d c(b[0], b[1], b[2]);
    if (rotated) {
      Eigen::Isometry3d X_WC = X;
      X_WC.translation() = X * c;
      scene.add_box(Eigen::Vector3d::Constant(b[3]), X_WC, name);
    } else {
      by_side[b[3]].push_back(c + X.translation());
    }
  }
  for (auto& [side, centres] : by_side) scene.add_cells(std::move(centres), side, name);
}

}  // namespace

FclScene scene_from_fcl(const std::vector<const ::fcl::CollisionObjectd*>& objects) {
  FclScene out;
  check::Scene& scene = out.scene;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string name = "scene object " + std::to_string(i);
    if (objects[i] == nullptr || !objects[i]->collisionGeometry())
      throw std::invalid_argument(name + ": null or without geometry");
    const ::fcl::CollisionGeometryd& g = *objects[i]->collisionGeometry();
    const Eigen::Isometry3d X = objects[i]->getTransform();
    switch (g.getNodeType()) {
      case ::fcl::GEOM_BOX:
        scene.add_box(static_cast<const ::fcl::Boxd&>(g).side, X, name);
        break;
      case ::fcl::GEOM_SPHERE:
        scene.add_sphere(X.translation(), static_cast<const ::fcl::Sphered&>(g).radius, name);
        break;
      case ::fcl::GEOM_CAPSULE: {
        const auto& c = static_cast<const ::fcl::Capsuled&>(g);
        scene.add_capsule(c.radius, c.lz, X, name);
        break;
      }
      case ::fcl::GEOM_CYLINDER: {
        const auto& c = static_cast<const ::fcl::Cylinderd&>(g);
        scene.add_cylinder(c.radius, c.lz, X, name);
        break;
      }
      case ::fcl::GEOM_OCTREE:
        add_octree(static_cast<const ::fcl::OcTreed&>(g), X, name, scene);
        break;
      default:
        if (!add_bvh<::fcl::OBBRSSd>(g, X, name, scene) &&
            !add_bvh<::fcl::AABBd>(g, X, name, scene) && !add_bvh<::fcl::OBBd>(g, X, name, scene) &&
            !add_bvh<::fcl::RSSd>(g, X, name, scene))
          throw std::invalid_argument(name + ": a geometry the robot checker does not take");
    }
    out.source.resize(scene.size(), i);
  }
  return out;
}

}  // namespace medspheres::fcl
