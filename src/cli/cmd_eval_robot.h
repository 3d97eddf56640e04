#pragma once
// medspheres eval ROBOT.urdf SPHERES: the fit of a robot's sphere file, link by link.

#include <map>
#include <string>
#include <vector>

#include "medspheres/bake/fit_metrics.h"

namespace medspheres::cli {

struct RobotEvalArgs {
  std::string urdf;
  std::string spheres;                ///< any robot-level sphere file
  std::vector<std::string> packages;  ///< PKG=DIR
  bool json = false;
  FitOptions fit;
};

/// The spheres of every link in a robot-level sphere file (any format convert reads): a
/// robot file gives each link's inner set, or its outer set where it has no inner one.
/// \throws InputError naming \p path for a file that holds one sphere set, not a robot's.
std::map<std::string, SphereSet> read_robot_spheres(const std::string& path);

/// True when \p path names a robot description (ends in .urdf, any case).
bool is_robot_description(const std::string& path);

/// Prints one row per link (text or JSON) and returns the exit code.
int run_eval_robot(const RobotEvalArgs& args);

}  // namespace medspheres::cli
