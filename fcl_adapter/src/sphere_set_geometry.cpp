#include "medspheres/fcl/sphere_set_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <Eigen/Eigenvalues>

namespace medspheres::fcl {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

const SphereSet& checked(const SphereSet& set) {
  validate_sphere_set(set, "sphere set");
  if (set.empty()) throw std::invalid_argument("SphereSetGeometry: the sphere set is empty");
  return set;
}

// The eight corners of a box that contains every sphere, along the principal axes of the
// centres (a right-handed frame), indexed by bits x + 2 y + 4 z (bit set: maximum side).
std::shared_ptr<const std::vector<::fcl::Vector3d>> guard_box_corners(const SphereSet& set) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Sphere& s : set.spheres) mean += s.center;
  mean /= static_cast<double>(set.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Sphere& s : set.spheres)
    cov.noalias() += (s.center - mean) * (s.center - mean).transpose();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  if (solver.info() == Eigen::Success) {
    axes.col(0) = solver.eigenvectors().col(2).normalized();
    axes.col(1) = solver.eigenvectors().col(1).normalized();
    axes.col(2) = axes.col(0).cross(axes.col(1)).normalized();
    if (!axes.allFinite()) axes.setIdentity();
  }
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Sphere& s : set.spheres) {
    const Eigen::Vector3d x = axes.transpose() * s.center;
    lo = lo.cwiseMin(x - Eigen::Vector3d::Constant(s.radius));
    hi = hi.cwiseMax(x + Eigen::Vector3d::Constant(s.radius));
  }
  // Rounding of the projections: widen by a few ulps of the extent.
  const double margin = 16 * kEps * std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  lo.array() -= margin;
  hi.array() += margin;
  auto corners = std::make_shared<std::vector<::fcl::Vector3d>>();
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d local((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(),
                                (k & 4) ? hi.z() : lo.z());
    corners->push_back(axes * local);
  }
  return corners;
}

// The box's six faces, counter-clockwise seen from outside, in fcl::Convex's format
// (vertex count, then the indices).
std::shared_ptr<const std::vector<int>> guard_box_faces() {
  return std::make_shared<const std::vector<int>>(std::vector<int>{
      4, 0, 4, 6, 2,  // -x
      4, 1, 3, 7, 5,  // +x
      4, 0, 1, 5, 4,  // -y
      4, 2, 6, 7, 3,  // +y
      4, 0, 2, 3, 1,  // -z
      4, 4, 5, 7, 6,  // +z
  });
}

}  // namespace

SphereSetGeometry::SphereSetGeometry(const SphereSet& set, const SphereTreeOptions& options)
    : ::fcl::Convex<double>(guard_box_corners(checked(set)), 6, guard_box_faces(), true),
      set_(set),
      tree_(set, options) {}

void SphereSetGeometry::computeLocalAABB() {
  ::fcl::AABBd box;
  box.min_ = set_.bounds().min();
  box.max_ = set_.bounds().max();
  aabb_local = box;
  aabb_center = box.center();
  double radius = 0.0;
  for (const Sphere& s : set_.spheres)
    radius = std::max(radius, (s.center - aabb_center).norm() + s.radius);
  aabb_radius = radius + 16 * kEps * (aabb_center.norm() + radius);
}

double SphereSetGeometry::computeVolume() const {
  throw std::logic_error("SphereSetGeometry: the volume of a union of balls is not provided");
}

::fcl::Vector3d SphereSetGeometry::computeCOM() const {
  throw std::logic_error(
      "SphereSetGeometry: the centre of mass of a union of balls is not provided");
}

::fcl::Matrix3d SphereSetGeometry::computeMomentofInertia() const {
  throw std::logic_error(
      "SphereSetGeometry: the moment of inertia of a union of balls is not provided");
}

const SphereSetGeometry* as_sphere_set(const ::fcl::CollisionGeometryd* geometry) noexcept {
  return dynamic_cast<const SphereSetGeometry*>(geometry);
}

}  // namespace medspheres::fcl
