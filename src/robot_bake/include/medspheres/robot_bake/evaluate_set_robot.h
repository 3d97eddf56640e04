#pragma once
/// \file
/// What `medspheres eval ROBOT.urdf SPHERES` measures, as one call for every tool (the CLI,
/// the Python module): each link's spheres against that link's solid, in the link's frame
/// (metres), by evaluate_robot_fit (robot_fit.h).

#include <map>
#include <string>
#include <vector>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/robot_fit.h"
#include "medspheres/sphere_set.h"

namespace medspheres {

/// The spheres of every link in a robot-level sphere file (any format `convert` reads): a
/// robot file (.robot.json) gives each link's inner set, or its outer set where it has no
/// inner one.
/// \throws InputError naming \p path for a file that holds one sphere set, not a robot's,
///   and as read_sphere_document and load_robot.
std::map<std::string, SphereSet> read_robot_spheres(const std::string& path);

struct RobotEvaluation {
  std::string urdf;            ///< the URDF as given
  std::string spheres_file;    ///< the spheres' name (their file)
  std::vector<LinkFit> links;  ///< one row per link of the URDF, in its order
  /// Links of the sphere file that the robot lacks (a planner's file often carries the links
  /// of other variants of a robot), in name order; not measured.
  std::vector<std::string> unknown_links;
};

/// Reads the URDF \p urdf (with \p read) and its link solids, and measures \p spheres (link
/// name -> spheres in that link's frame; named \p spheres_file in errors) against them; the
/// links the robot lacks are listed in `unknown_links`, not measured.
/// \throws InputError naming \p spheres_file when none of its links is a link of the robot,
///   and as read_urdf, load_link_solids and evaluate_robot_fit.
RobotEvaluation evaluate_robot_spheres(const std::string& urdf, const UrdfReadOptions& read,
                                       const std::map<std::string, SphereSet>& spheres,
                                       const std::string& spheres_file, const FitOptions& options);

/// evaluate_robot_spheres of read_robot_spheres(\p spheres_file) (which is read first).
RobotEvaluation evaluate_robot_file(const std::string& urdf, const UrdfReadOptions& read,
                                    const std::string& spheres_file, const FitOptions& options);

/// The JSON object `medspheres eval ROBOT SPHERES --json` prints: "urdf", "spheres_file",
/// "links" (one object per row: link, spheres, primitives, note and, where measured, nerr,
/// nerr_kind, max_protrusion, mc_error, uncovered_max, uncovered_mean, surface_certificate
/// (as `eval` of a mesh writes it), warnings; NaN and infinities as null), "unknown_links".
/// Indented by two spaces.
std::string robot_evaluation_json(const RobotEvaluation& evaluation);

}  // namespace medspheres
