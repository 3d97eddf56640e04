#pragma once
/// \file
/// The orthographic cameras of the standard views. World frame W and units: the mesh's
/// and the sphere set's. A camera looks along `forward`, `right` x `up` spans the image,
/// every pixel is a square of side `pixel` (world units), and every ray starts outside
/// the ball it was framed on, so a ray starts outside every sphere and outside the solid.

#include <string>

#include <Eigen/Core>

namespace medspheres::render {

/// iso: from (+1, -1, +1) towards the centre; front: along +y; side: along -x; top:
/// along -z. grid: the four in a 2 x 2 image (iso, front / side, top).
enum class View { iso, front, side, top, grid };

/// "iso", "front", "side", "top", "grid".
std::string to_string(View view);
/// \throws InputError (source "--view") for any other name.
View parse_view(const std::string& name);

struct OrthoCamera {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< the image centre's ray passes here
  Eigen::Vector3d forward = Eigen::Vector3d::UnitY();
  Eigen::Vector3d right = Eigen::Vector3d::UnitX();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double pixel = 1.0;         ///< side of a pixel, world units
  double back_off = 1.0;      ///< rays start this far behind the centre's plane
  int width = 1, height = 1;  ///< pixels

  /// The ray of pixel (column x, row y; row 0 on top) through the pixel's centre.
  Eigen::Vector3d ray_origin(int x, int y) const;
};

/// The camera of a single view (not grid) that frames the box [lo, hi] in a width x
/// height image: the box's circumscribed ball, with a 5 % margin, fills the shorter side.
/// \throws std::invalid_argument for View::grid, an empty or non-finite box, or a size < 1.
OrthoCamera frame_camera(View view, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int width,
                         int height);

}  // namespace medspheres::render
