#pragma once
// FCL-side oracles for the adapter tests: one sphere of a set answered by FCL's own
// narrowphase (an fcl::Sphere against the other geometry), BVHModels built from a
// TriangleMesh, and the tolerance settings of the abs_err / rel_err tests. Header-only. Inside
// namespace medspheres, ::fcl must be spelled out: medspheres::fcl is the adapter's namespace.

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <fcl/fcl.h>

#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::test {

/// Pose in W of an fcl::Sphere standing for sphere s of a set posed at X_WA.
inline ::fcl::Transform3d sphere_pose(const Sphere& s, const Eigen::Isometry3d& X_WA) {
  ::fcl::Transform3d X = ::fcl::Transform3d::Identity();
  X.translation() = X_WA * s.center;
  return X;
}

/// FCL's answer for one sphere against a geometry.
struct FclAnswer {
  bool collides = false;
  double distance = std::numeric_limits<double>::infinity();  ///< when separated
  double depth = 0.0;                                         ///< when colliding
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();           ///< when colliding
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();              ///< FCL's contact position
  Eigen::Vector3d p_sphere = Eigen::Vector3d::Zero();         ///< nearest points when separated
  Eigen::Vector3d p_other = Eigen::Vector3d::Zero();
  /// Signed distance: distance when separated, -depth when colliding.
  double signed_distance() const { return collides ? -depth : distance; }
};

/// FCL's fcl::Sphere narrowphase: fcl::collide for contact, fcl::distance when apart.
/// \p use_distance false skips fcl::distance (libfcl cannot compute sphere-plane and
/// sphere-halfspace distances); the caller then supplies the distance.
inline FclAnswer fcl_sphere_answer(const Sphere& s, const Eigen::Isometry3d& X_WA,
                                   const ::fcl::CollisionGeometryd* other,
                                   const ::fcl::Transform3d& X_WB, bool use_distance = true) {
  FclAnswer out;
  const ::fcl::Sphered ball(s.radius);
  const ::fcl::Transform3d X_WS = sphere_pose(s, X_WA);
  ::fcl::CollisionRequestd creq(1, true);
  ::fcl::CollisionResultd cres;
  ::fcl::collide(&ball, X_WS, other, X_WB, creq, cres);
  if (cres.isCollision()) {
    out.collides = true;
    out.depth = cres.getContact(0).penetration_depth;
    out.normal = cres.getContact(0).normal;
    out.pos = cres.getContact(0).pos;
    return out;
  }
  if (use_distance) {
    ::fcl::DistanceRequestd dreq(true);
    ::fcl::DistanceResultd dres;
    out.distance = ::fcl::distance(&ball, X_WS, other, X_WB, dreq, dres);
    out.p_sphere = dres.nearest_points[0];
    out.p_other = dres.nearest_points[1];
  }
  return out;
}

/// A BVHModel of any BV type holding the mesh.
template <class BV>
std::shared_ptr<::fcl::BVHModel<BV>> make_bvh(const TriangleMesh& mesh) {
  auto model = std::make_shared<::fcl::BVHModel<BV>>();
  std::vector<::fcl::Triangle> tris;
  for (const auto& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
  model->beginModel();
  model->addSubModel(mesh.vertices, tris);
  model->endModel();
  return model;
}

/// FCL's sphere-triangle core: the squared distance from the centre to the triangle
/// (fcl::detail::Project), so the signed distance sqrt(.) - r; overlap when <= r^2.
inline double fcl_sphere_triangle_signed_distance(const Eigen::Vector3d& c, double r,
                                                  const Eigen::Vector3d& a,
                                                  const Eigen::Vector3d& b,
                                                  const Eigen::Vector3d& d) {
  const auto result = ::fcl::detail::Project<double>::projectTriangle(a, b, d, c);
  return std::sqrt(result.sqr_distance) - r;
}

/// FCL's point of triangle (a, b, d) nearest to c (fcl::detail::Project), from its
/// barycentric parameterization. The triangle must not be degenerate.
inline Eigen::Vector3d fcl_closest_point_on_triangle(const Eigen::Vector3d& c,
                                                     const Eigen::Vector3d& a,
                                                     const Eigen::Vector3d& b,
                                                     const Eigen::Vector3d& d) {
  const auto result = ::fcl::detail::Project<double>::projectTriangle(a, b, d, c);
  return result.parameterization[0] * a + result.parameterization[1] * b +
         result.parameterization[2] * d;
}

/// The contact position documented in sphere_set_geometry.h for a ball (centre c, radius
/// r) in contact with a primitive with penetration depth \p depth along the unit normal n
/// (from the ball into the primitive): the midpoint of the two deepest points, c + r n on
/// the ball and c + (r - depth) n on the primitive.
inline Eigen::Vector3d documented_contact_position(const Eigen::Vector3d& c, double r, double depth,
                                                   const Eigen::Vector3d& n) {
  return c + (r - 0.5 * depth) * n;
}

/// One setting of a DistanceRequest's tolerances for the abs_err / rel_err tests. abs_err
/// is a fraction of the scene's exact distance d*, or 1e6, which stands for a tolerance
/// that never binds. `loose` when both bind: FCL's rule then prunes, and some answers
/// exceed d* (within the guarantee); with one tolerance alone the answer stays exact.
struct ToleranceMode {
  const char* name;
  double abs_err;
  double rel_err;
  bool loose;
  /// The request's abs_err for a scene whose exact distance is \p exact.
  double abs_err_for(double exact) const { return abs_err < 1e6 ? abs_err * exact : abs_err; }
};

inline const std::vector<ToleranceMode> kToleranceModes = {{"exact", 0, 0, false},
                                                           {"rel_err 0.5", 1e6, 0.5, true},
                                                           {"abs_err 0.5 d*", 0.5, 1e6, true},
                                                           {"rel_err alone", 0, 0.5, false},
                                                           {"abs_err alone", 0.5, 0, false}};

}  // namespace medspheres::test
