#pragma once
// One piece of a check::Scene in W, as the grid stores it: a sphere, an oriented box, a
// capsule, a cylinder, a triangle, a point or an axis-aligned cell, with its exact
// squared distance from a point to its core (the element minus its radius).

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/check/scene.h"
#include "medspheres/point_triangle.h"

namespace medspheres::check::detail {

enum class ElementKind : std::uint8_t { sphere, box, capsule, cylinder, triangle, point, cell };

struct Element {
  ElementKind kind = ElementKind::point;
  std::uint32_t object = 0;  // index into Scene::objects()
  // sphere, capsule: the radius around the core (a point, a segment); 0 for the others.
  double radius = 0.0;
  // point, sphere: a = centre. cell: a = centre, b = half sides. box: a = centre, b = half
  // sides, R = R_WB. capsule: segment from a to a + b, length2 = |b|^2. cylinder: a =
  // centre, b = unit axis, length2 = half length, cylinder_radius.
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  double length2 = 0.0, cylinder_radius = 0.0;
  medspheres::detail::QueryTriangle triangle;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::AlignedBox3d box;  // contains the element
  // A ball that contains the element: centre ball_centre, radius ball_radius.
  Eigen::Vector3d ball_centre = Eigen::Vector3d::Zero();
  double ball_radius = 0.0;
};

/// The squared distance from p to the element's core; p is within d of the element when
/// it is <= (d + radius)^2 (d + radius >= 0).
double core_distance_sq(const Element& e, const Eigen::Vector3d& p);

/// The element's exact distance to p (0 inside a solid), rounded as computed.
double element_distance(const Element& e, const Eigen::Vector3d& p);

/// Whether p lies within rq of the element (closed: touching counts), rq may be negative.
inline bool element_within(const Element& e, const Eigen::Vector3d& p, double rq) {
  const double reach = rq + e.radius;
  return reach >= 0.0 && core_distance_sq(e, p) <= reach * reach;
}

/// Every object of the scene as elements.
std::vector<Element> scene_elements(const Scene& scene);

}  // namespace medspheres::check::detail
