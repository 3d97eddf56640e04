#pragma once
// Closed forms for balls, the oracles of the volume and area tests. Header-only.

namespace medspheres::test {

constexpr double kPi = 3.141592653589793238462643383279502884;

inline double ball_volume(double r) {
  return 4.0 / 3.0 * kPi * r * r * r;
}

inline double sphere_area(double r) {
  return 4.0 * kPi * r * r;
}

/// Volume of the part of a ball of radius r beyond a plane at distance r - h from its centre.
inline double cap_volume(double r, double h) {
  return kPi * h * h * (3.0 * r - h) / 3.0;
}

/// Volume of the lens of two balls whose spheres cross (centres at distance d), in the
/// textbook form pi (r1 + r2 - d)^2 (d^2 + 2 d (r1 + r2) - 3 (r1 - r2)^2) / (12 d); the
/// library sums two caps instead.
inline double lens_volume(double r1, double r2, double d) {
  const double o = r1 + r2 - d;
  return kPi * o * o * (d * d + 2.0 * d * (r1 + r2) - 3.0 * (r1 - r2) * (r1 - r2)) / (12.0 * d);
}

/// Area of sphere 1 inside ball 2, centres at distance d (Archimedes: 2 pi r1 times the
/// height of the cap).
inline double cap_area(double r1, double r2, double d) {
  return 2.0 * kPi * r1 * (r2 * r2 - (d - r1) * (d - r1)) / (2.0 * d);
}

}  // namespace medspheres::test
