// The bounding test before a sphere tree walk (pair_beyond.h). Each bound is the distance
// from the set's bounding ball to a solid that contains g, in g's frame G: a ball, a BVH's
// root RSS, or the shape itself (a box, a ball, a capsule; a cylinder exactly, by its
// radial and axial excess). The magnitudes that scale the rounding allowance are the
// ball's and g's positions and sizes.

#include "pair_beyond.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>

#include "fcl_bv_rss.h"
#include "fcl_geometry_visit.h"
#include "gap_allowance.h"

namespace medspheres::fcl::detail {
namespace {

// The set's bounding ball, centre p in G, against g's bound; scale: the magnitudes of the
// ball's and g's positions.
struct BeyondBound {
  Eigen::Vector3d p;
  double r;
  double scale;
  double margin;

  // Whether sqrt(d2) - sub exceeds the margin; size: g's magnitude.
  bool beyond(double d2, double sub, double size) const {
    return squared_gap_beyond(d2, sub, scale + size, margin);
  }

  template <class BV>
  bool operator()(const ::fcl::BVHModel<BV>& m) const {
    if (m.getModelType() != ::fcl::BVH_MODEL_TRIANGLES || m.getNumBVs() == 0 ||
        (m.build_state != ::fcl::BVH_BUILD_STATE_PROCESSED &&
         m.build_state != ::fcl::BVH_BUILD_STATE_UPDATED))
      return false;
    const BV& bv = m.getBV(0).bv;
    if constexpr (std::is_same_v<BV, ::fcl::OBBRSSd> || std::is_same_v<BV, ::fcl::RSSd>) {
      const ::fcl::RSSd& b = rss_part(bv);  // as rss_of(bv), without the copy
      return beyond(rectangle_distance2(b.axis, b.To, b.l[0], b.l[1], p), b.r + r,
                    b.To.cwiseAbs().sum() + b.l[0] + b.l[1] + b.r);
    } else {
      const Rss b = rss_of(bv);
      return beyond(rectangle_distance2(b, p), b.radius + r,
                    b.corner.cwiseAbs().sum() + b.length.sum() + b.radius);
    }
  }

  static const ::fcl::RSSd& rss_part(const ::fcl::RSSd& bv) { return bv; }
  static const ::fcl::RSSd& rss_part(const ::fcl::OBBRSSd& bv) { return bv.rss; }

  bool operator()(const Shape& shape) const {
    const ::fcl::CollisionGeometryd& g = shape.geometry;
    switch (shape.type) {
      case ::fcl::GEOM_BOX: {
        const Eigen::Vector3d h = 0.5 * static_cast<const ::fcl::Boxd&>(g).side;
        return beyond((p.cwiseAbs() - h).cwiseMax(0.0).squaredNorm(), r, h.sum());
      }
      case ::fcl::GEOM_SPHERE: {
        const double rho = static_cast<const ::fcl::Sphered&>(g).radius;
        return beyond(p.squaredNorm(), r + rho, rho);
      }
      case ::fcl::GEOM_CAPSULE: {
        const auto& c = static_cast<const ::fcl::Capsuled&>(g);
        const double h = 0.5 * c.lz;
        const Eigen::Vector3d axis_point(0.0, 0.0, std::clamp(p.z(), -h, h));
        return beyond((p - axis_point).squaredNorm(), r + c.radius, h + c.radius);
      }
      case ::fcl::GEOM_CYLINDER: {
        const auto& c = static_cast<const ::fcl::Cylinderd&>(g);
        const double radial = std::max(std::hypot(p.x(), p.y()) - c.radius, 0.0);
        const double axial = std::max(std::abs(p.z()) - 0.5 * c.lz, 0.0);
        return beyond(radial * radial + axial * axial, r, c.lz + c.radius);
      }
      default:
        return false;
    }
  }

#if FCL_HAVE_OCTOMAP
  bool operator()(const ::fcl::OcTreed&) const {
    return false;
  }
#endif
  bool operator()(const Unsupported&) const {
    return false;
  }
};

}  // namespace

bool pair_beyond(const SphereSetGeometry& s, const ::fcl::Transform3d& X_WS,
                 const ::fcl::CollisionGeometryd& g, const SphereSetGeometry* g_set,
                 const ::fcl::Transform3d& X_WG, double margin) {
  if (!std::isfinite(margin)) return false;
  const Sphere& b = s.bounding_ball();
  const Eigen::Vector3d c_W = X_WS * b.center;
  // Magnitudes (the allowance's scale): sums of absolute coordinates, at least the norms.
  const double scale = c_W.cwiseAbs().sum() + b.radius + X_WG.translation().cwiseAbs().sum();
  if (g_set != nullptr) {
    const Sphere& o = g_set->bounding_ball();
    const Eigen::Vector3d o_W = X_WG * o.center;
    return squared_gap_beyond((o_W - c_W).squaredNorm(), b.radius + o.radius,
                              scale + o_W.cwiseAbs().sum() + o.radius, margin);
  }
  const Eigen::Vector3d p_G = X_WG.linear().transpose() * (c_W - X_WG.translation());
  return visit_geometry(g, BeyondBound{p_G, b.radius, scale, margin});
}

}  // namespace medspheres::fcl::detail
