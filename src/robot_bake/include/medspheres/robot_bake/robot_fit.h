#pragma once
/// \file
/// The fit of a robot's spheres, link by link: each link's spheres against that link's solid
/// (link_solid.h) in the link frame, by the fit metrics (fit_metrics.h) and the certificate
/// of surface coverage (cover_certificate.h). `eval` of a robot (evaluate_set_robot.h) and
/// the robot bake's tests call it.

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

/// The fit of one link's spheres to its solid (fit_metrics.h), in the link frame.
struct LinkFit {
  std::string link;
  std::size_t spheres = 0;     ///< in the file for this link
  std::size_t primitives = 0;  ///< of them, equal to a sphere primitive of the link
  /// Of the other spheres against the link's meshed parts (placed_mesh); empty when the
  /// link has no meshed part or no other sphere.
  std::optional<FitReport> fit;
  /// Whether all the link's spheres (primitives included) cover the surface of its meshed
  /// parts (cover_certificate.h); present exactly when `fit` is.
  std::optional<CoverCertificate> certificate;
  std::string note;  ///< why there is no fit ("no collision geometry", "no spheres", ...)
};

/// Measures each link's spheres (\p spheres: link name -> spheres in its frame; links
/// missing from it have none) against its solid. A sphere equal to one of the link's sphere
/// primitives (centre within 1e-6 of its radius, radius within 1e-6 relative) is exact by
/// construction and counted in `primitives`, not measured; the rest are measured against
/// the meshed parts, whose union is the rest of the solid; every sphere of the link takes
/// part in the certificate of the meshed parts' surface. Links in \p solids' order.
/// \throws InputError (source \p spheres_source) for a link name in \p spheres that is
///   not a link of the robot, and as FitEvaluator::evaluate.
std::vector<LinkFit> evaluate_robot_fit(const std::vector<LinkSolid>& solids,
                                        const std::map<std::string, SphereSet>& spheres,
                                        const std::string& spheres_source,
                                        const FitOptions& options = {});

}  // namespace medspheres
