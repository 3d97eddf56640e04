#pragma once
// Private to the fcl_adapter target: the one list of the FCL geometries a sphere set is
// answered against, as a visit over their concrete types.

#include <fcl/config.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>
#include <fcl/narrowphase/collision_object.h>
#if FCL_HAVE_OCTOMAP
#include <fcl/geometry/octree/octree.h>
#endif

namespace medspheres::fcl::detail {

// What visit_geometry passes for a primitive the dispatch supports, and for a geometry it
// does not support.
struct Shape {
  const ::fcl::CollisionGeometryd& geometry;
  ::fcl::NODE_TYPE type;  ///< geometry.getNodeType()
};
struct Unsupported {
  ::fcl::NODE_TYPE type;
};

// The one list of the geometries a sphere set is answered against: calls v with the
// fcl::BVHModel<BV> of a BVH of a supported BV type, Shape for a supported primitive, the
// fcl::OcTree of an octree, or Unsupported.
template <class V>
auto visit_geometry(const ::fcl::CollisionGeometryd& g, V&& v) {
  const ::fcl::NODE_TYPE type = g.getNodeType();
  switch (g.getObjectType()) {
    case ::fcl::OT_BVH:
      switch (type) {
        case ::fcl::BV_AABB:
          return v(static_cast<const ::fcl::BVHModel<::fcl::AABBd>&>(g));
        case ::fcl::BV_OBB:
          return v(static_cast<const ::fcl::BVHModel<::fcl::OBBd>&>(g));
        case ::fcl::BV_RSS:
          return v(static_cast<const ::fcl::BVHModel<::fcl::RSSd>&>(g));
        case ::fcl::BV_kIOS:
          return v(static_cast<const ::fcl::BVHModel<::fcl::kIOSd>&>(g));
        case ::fcl::BV_OBBRSS:
          return v(static_cast<const ::fcl::BVHModel<::fcl::OBBRSSd>&>(g));
        case ::fcl::BV_KDOP16:
          return v(static_cast<const ::fcl::BVHModel<::fcl::KDOP<double, 16>>&>(g));
        case ::fcl::BV_KDOP18:
          return v(static_cast<const ::fcl::BVHModel<::fcl::KDOP<double, 18>>&>(g));
        case ::fcl::BV_KDOP24:
          return v(static_cast<const ::fcl::BVHModel<::fcl::KDOP<double, 24>>&>(g));
        default:
          break;
      }
      break;
    case ::fcl::OT_GEOM:
      switch (type) {
        case ::fcl::GEOM_BOX:
        case ::fcl::GEOM_SPHERE:
        case ::fcl::GEOM_ELLIPSOID:
        case ::fcl::GEOM_CAPSULE:
        case ::fcl::GEOM_CONE:
        case ::fcl::GEOM_CYLINDER:
        case ::fcl::GEOM_CONVEX:
        case ::fcl::GEOM_PLANE:
        case ::fcl::GEOM_HALFSPACE:
          return v(Shape{g, type});
        default:
          break;
      }
      break;
#if FCL_HAVE_OCTOMAP
    case ::fcl::OT_OCTREE:
      return v(static_cast<const ::fcl::OcTreed&>(g));
#endif
    default:
      break;
  }
  return v(Unsupported{type});
}

}  // namespace medspheres::fcl::detail
