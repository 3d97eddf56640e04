#pragma once
// Private to the fcl_adapter target: FCL's bounding volumes as RSS in the model's frame
// (each RSS contains its BV), and the distance from a point to an RSS's rectangle.

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>

#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kDOP.h>
#include <fcl/math/bv/kIOS.h>

#include "medspheres/rss.h"

namespace medspheres::fcl::detail {

inline Rss rss_of_box(const Eigen::Vector3d& center, const Eigen::Matrix3d& axes,
                      const Eigen::Vector3d& half) {
  // The rectangle spans the two largest extents; the smallest becomes the radius. The
  // box lies inside: each of its points is within the smallest half extent of it.
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return half[i] > half[j]; });
  Rss rss;
  rss.axis.col(0) = axes.col(order[0]);
  rss.axis.col(1) = axes.col(order[1]);
  rss.axis.col(2) = rss.axis.col(0).cross(rss.axis.col(1));
  rss.length = Eigen::Vector2d(2 * half[order[0]], 2 * half[order[1]]);
  rss.corner = center - rss.axis.col(0) * half[order[0]] - rss.axis.col(1) * half[order[1]];
  rss.radius =
      half[order[2]] + 16 * std::numeric_limits<double>::epsilon() * (center.norm() + half.sum());
  return rss;
}

inline Rss rss_of(const ::fcl::AABBd& bv) {
  return rss_of_box(bv.center(), Eigen::Matrix3d::Identity(), 0.5 * (bv.max_ - bv.min_));
}

inline Rss rss_of(const ::fcl::OBBd& bv) {
  return rss_of_box(bv.To, bv.axis, bv.extent);
}

inline Rss rss_of(const ::fcl::RSSd& bv) {
  Rss rss;
  rss.corner = bv.To;
  rss.radius = bv.r;
  if (bv.l[0] >= bv.l[1]) {
    rss.axis = bv.axis;
    rss.length = Eigen::Vector2d(bv.l[0], bv.l[1]);
  } else {
    rss.axis.col(0) = bv.axis.col(1);
    rss.axis.col(1) = bv.axis.col(0);
    rss.axis.col(2) = -bv.axis.col(2);
    rss.length = Eigen::Vector2d(bv.l[1], bv.l[0]);
  }
  return rss;
}

inline Rss rss_of(const ::fcl::OBBRSSd& bv) {
  return rss_of(bv.rss);
}

inline Rss rss_of(const ::fcl::kIOSd& bv) {
  return rss_of(bv.obb);
}

template <std::size_t N>
inline Rss rss_of(const ::fcl::KDOP<double, N>& bv) {
  // The first three slab pairs are the axis-aligned ones.
  ::fcl::AABBd box;
  for (int i = 0; i < 3; ++i) {
    box.min_[i] = bv.dist(static_cast<std::size_t>(i));
    box.max_[i] = bv.dist(N / 2 + static_cast<std::size_t>(i));
  }
  return rss_of(box);
}

/// The squared distance from p to the rectangle {corner + s x + t y : 0 <= s <= l0,
/// 0 <= t <= l1}, x and y the first two columns of the orthonormal \p axis (fcl::RSS's
/// To, axis and l, in either order of the sides), all in one frame.
inline double rectangle_distance2(const Eigen::Matrix3d& axis, const Eigen::Vector3d& corner,
                                  double l0, double l1, const Eigen::Vector3d& p) {
  const Eigen::Vector3d t = axis.transpose() * (p - corner);
  const Eigen::Vector3d off(t.x() - std::clamp(t.x(), 0.0, l0), t.y() - std::clamp(t.y(), 0.0, l1),
                            t.z());
  return off.squaredNorm();
}

/// The squared distance from p to the rectangle of the RSS b, both in one frame.
inline double rectangle_distance2(const Rss& b, const Eigen::Vector3d& p) {
  return rectangle_distance2(b.axis, b.corner, b.length[0], b.length[1], p);
}

}  // namespace medspheres::fcl::detail
