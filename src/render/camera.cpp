#include "medspheres/render/camera.h"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Geometry>

#include "medspheres/error.h"

namespace medspheres::render {

std::string to_string(View view) {
  switch (view) {
    case View::iso:
      return "iso";
    case View::front:
      return "front";
    case View::side:
      return "side";
    case View::top:
      return "top";
    case View::grid:
      return "grid";
  }
  return "?";
}

View parse_view(const std::string& name) {
  for (View v : {View::iso, View::front, View::side, View::top, View::grid})
    if (to_string(v) == name) return v;
  throw InputError::option(ErrorKind::kOutOfRange, "view", "",
                           "must be iso, front, side, top or grid, got \"" + name + "\"");
}

Eigen::Vector3d OrthoCamera::ray_origin(int x, int y) const {
  const double u = (x + 0.5 - 0.5 * width) * pixel;
  const double v = (0.5 * height - (y + 0.5)) * pixel;
  return center + u * right + v * up - back_off * forward;
}

OrthoCamera frame_camera(View view, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int width,
                         int height) {
  if (view == View::grid) throw std::invalid_argument("frame_camera: grid is not one view");
  if (width < 1 || height < 1) throw std::invalid_argument("frame_camera: size must be >= 1");
  if (!lo.allFinite() || !hi.allFinite() || (hi - lo).minCoeff() < 0.0)
    throw std::invalid_argument("frame_camera: the box must be finite and not empty");
  OrthoCamera c;
  switch (view) {
    case View::front:
      c.forward = {0, 1, 0}, c.up = {0, 0, 1};
      break;
    case View::side:
      c.forward = {-1, 0, 0}, c.up = {0, 0, 1};
      break;
    case View::top:
      c.forward = {0, 0, -1}, c.up = {0, 1, 0};
      break;
    default:
      c.forward = Eigen::Vector3d(-1, 1, -1).normalized();
      c.up = (Eigen::Vector3d::UnitZ() - c.forward.z() * c.forward).normalized();
  }
  c.right = c.forward.cross(c.up);
  c.center = 0.5 * (lo + hi);
  // A box of one point still gets a picture, two units across.
  const double half_diagonal = 0.5 * (hi - lo).norm();
  const double radius = half_diagonal > 0.0 ? half_diagonal : 1.0;
  c.width = width;
  c.height = height;
  c.pixel = 2.0 * 1.05 * radius / std::min(width, height);
  c.back_off = 2.0 * radius;
  return c;
}

}  // namespace medspheres::render
