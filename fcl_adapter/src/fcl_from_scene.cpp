#include "medspheres/fcl/fcl_from_scene.h"

#include <stdexcept>
#include <string>

#include <fcl/fcl.h>

#include "medspheres/fcl/bounded_geometry.h"

namespace medspheres::fcl {
namespace {

using Geometry = std::shared_ptr<::fcl::CollisionGeometryd>;

void add(FclObjects& out, Geometry g, const Eigen::Isometry3d& X_WO) {
  out.owned.push_back(std::make_unique<::fcl::CollisionObjectd>(std::move(g), X_WO));
  out.objects.push_back(out.owned.back().get());
}

void add_cells(FclObjects& out, const check::SceneObject& o) {
  const auto cube = std::make_shared<::fcl::Boxd>(Eigen::Vector3d::Constant(o.cell_side));
  for (const Eigen::Vector3d& c : o.points) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() = c;
    add(out, cube, X);
  }
}

Geometry geometry_of(const check::SceneObject& o) {
  switch (o.kind) {
    case check::ShapeKind::sphere:
      return std::make_shared<::fcl::Sphered>(o.radius);
    case check::ShapeKind::box:
      return std::make_shared<::fcl::Boxd>(o.size);
    case check::ShapeKind::capsule:
      return std::make_shared<::fcl::Capsuled>(o.radius, o.length);
    case check::ShapeKind::cylinder:
      return std::make_shared<::fcl::Cylinderd>(o.radius, o.length);
    case check::ShapeKind::mesh:
      return make_bvh_model<::fcl::OBBRSSd>(o.mesh);
    default:
      return nullptr;
  }
}

}  // namespace

FclObjects fcl_from_scene(const check::Scene& scene) {
  FclObjects out;
  for (std::size_t i = 0; i < scene.size(); ++i) {
    const check::SceneObject& o = scene.objects()[i];
    if (o.kind == check::ShapeKind::cells) {
      add_cells(out, o);
      continue;
    }
    if (o.kind == check::ShapeKind::points)
      throw std::invalid_argument("scene object " + std::to_string(i) + " \"" + o.name +
                                  "\": a point cloud has no FCL geometry for the mesh fallback; "
                                  "give its points as cells of the sensor's resolution");
    add(out, geometry_of(o), o.X_WO);
  }
  return out;
}

}  // namespace medspheres::fcl
