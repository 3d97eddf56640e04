#pragma once
/// \file
/// SphereSet: a finite set of closed balls, the object every part of medspheres produces
/// or consumes. Frame and units: those of the mesh the set approximates (frame M);
/// nothing here rescales or moves them.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace medspheres {

/// A closed ball {x : |x - center| <= radius}. A valid ball has finite coordinates, a
/// finite radius > 0 (subnormal radii included) and a finite bounding box (see
/// validate_sphere_set).
struct Sphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< p_MoC_M: centre, in frame M
  double radius = 0.0;                               ///< same units as center
};

/// The balls plus the provenance a sphere-set file carries beside them.
struct SphereSet {
  std::vector<Sphere> spheres;

  /// Every top-level key of the sphere-set file other than "format", "version" and
  /// "spheres", as the text of one JSON object ("{}" when there is none). It is kept
  /// verbatim, so that load followed by save loses nothing, including keys this
  /// version does not know. See io.h for the keys medspheres itself writes.
  std::string metadata_json = "{}";

  std::size_t size() const noexcept { return spheres.size(); }
  bool empty() const noexcept { return spheres.empty(); }

  /// The smallest axis-aligned box that contains every ball (empty box for an empty set).
  Eigen::AlignedBox3d bounds() const;
};

/// Checks that every ball has finite coordinates, a finite radius > 0 (however small:
/// subnormal radii are valid), and a finite bounding box (|centre coordinate| + radius
/// finite).
/// \param source the name used in the error message (a file name, or "sphere set").
/// \param allow_points also accept radius 0 (points; SphereTreeOptions::allow_points).
/// \throws InputError "<source>: sphere 17 has radius -0.5 (must be > 0)" and the like.
void validate_sphere_set(const SphereSet& set, const std::string& source,
                         bool allow_points = false);

}  // namespace medspheres
