#pragma once
// Lower bounds on the signed distance between the contents of two bounding volumes, used
// to prune the traversals in sphere_tree_query.cpp. Private to the runtime target.
//
// For convex sets X and Y and any unit vector d, the gap along d,
//   gap(d) = |d . (c_Y - c_X)| - h_X(d) - h_Y(d),   h(d) = support extent about the centre,
// is at most the signed distance of any ball inside X and any ball (or convex primitive)
// inside Y, whether they are apart or overlap. The direction only affects how tight the
// bound is. The traversals use the line of centres: it costs a few dot products, and on
// baked sphere sets the traversal then visits under ten percent more node pairs than
// with a tight rectangle-rectangle distance, at a fraction of the cost.

#include <cmath>

#include <Eigen/Core>

namespace medspheres::detail {

/// An RSS (or a ball, with zero half lengths) in centre form, in one frame.
struct RssView {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();   ///< centre of the rectangle
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();  ///< unit side directions
  Eigen::Vector3d v = Eigen::Vector3d::UnitY();
  double h0 = 0.0;  ///< half side lengths
  double h1 = 0.0;
  double r = 0.0;  ///< swept radius
};

/// Support extent of a rectangle with half sides h0, h1 along unit u, v, in direction
/// unit d, about its centre.
inline double rectangle_extent(double h0, double h1, const Eigen::Vector3d& u,
                               const Eigen::Vector3d& v, const Eigen::Vector3d& d) {
  return h0 * std::abs(d.dot(u)) + h1 * std::abs(d.dot(v));
}

/// gap(d) along the line of centres of two RSS given in one frame; \p fallback when the
/// centres coincide and the line is undefined.
inline double rss_gap(const RssView& a, const RssView& b, double fallback) {
  const Eigen::Vector3d w = b.c - a.c;
  const double len = w.norm();
  if (!(len > 0.0)) return fallback;
  const Eigen::Vector3d d = w / len;
  return len - rectangle_extent(a.h0, a.h1, a.u, a.v, d) -
         rectangle_extent(b.h0, b.h1, b.u, b.v, d) - a.r - b.r;
}

}  // namespace medspheres::detail
