#pragma once
// medspheres eval ROBOT.urdf SPHERES: the fit of a robot's sphere file, link by link.

#include <string>
#include <vector>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/robot_bake/evaluate_set_robot.h"

namespace medspheres::cli {

struct RobotEvalArgs {
  std::string urdf;
  std::string spheres;                ///< any robot-level sphere file
  std::vector<std::string> packages;  ///< PKG=DIR
  bool json = false;
  FitOptions fit;
};

/// True when \p path names a robot description (ends in .urdf, any case).
bool is_robot_description(const std::string& path);

/// Prints one row per link (text or JSON) and returns the exit code.
int run_eval_robot(const RobotEvalArgs& args);

}  // namespace medspheres::cli
