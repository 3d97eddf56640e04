#pragma once
/// \file
/// Rss: the rectangle-swept sphere of Larsen, Gottschalk, Lin and Manocha (1999), the
/// bounding volume of SphereTree's default nodes (paper §5.2). It is stored exactly as
/// fcl::RSS stores it, so that values can be copied field by field between the two.
///
/// Frames (monogram notation): F is the frame the RSS is expressed in (a tree's own
/// frame A, or a target's frame B). T is the rectangle's frame: its origin To is the
/// rectangle's minimum corner, its x axis runs along the side of length length[0], its
/// y axis along the side of length length[1], and its z axis is the rectangle's normal.
///
/// The RSS is the closed set of points within `radius` of the rectangle
///   {To + s x_T + t y_T : 0 <= s <= length[0], 0 <= t <= length[1]}.
/// Units are those of the coordinates.

#include <Eigen/Core>

namespace medspheres {

struct Rss {
  /// R_FT: the columns are x_T (along the longer side), y_T (along the shorter side)
  /// and z_T = x_T x y_T (the normal). Orthonormal and right-handed.
  Eigen::Matrix3d axis = Eigen::Matrix3d::Identity();
  /// p_FoTo_F: the rectangle's minimum corner (fcl::RSS::To).
  Eigen::Vector3d corner = Eigen::Vector3d::Zero();
  /// Side lengths along x_T and y_T (fcl::RSS::l); length[0] >= length[1] >= 0.
  Eigen::Vector2d length = Eigen::Vector2d::Zero();
  /// Radius of the swept sphere (fcl::RSS::r), >= 0.
  double radius = 0.0;

  /// p_FoC_F: the centre C of the rectangle, corner + (length[0] x_T + length[1] y_T) / 2,
  /// which is the RSS's centre of symmetry. (coal's RSS::center() returns the corner
  /// instead; this one does not.)
  Eigen::Vector3d center() const {
    return corner + axis.col(0) * (0.5 * length[0]) + axis.col(1) * (0.5 * length[1]);
  }
};

}  // namespace medspheres
