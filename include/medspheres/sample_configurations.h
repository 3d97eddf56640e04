#pragma once
/// \file
/// Joint configurations drawn within a robot's limits, for learning and for tests: the
/// one rule that RobotBounds' pair order, the self-collision matrix and RobotChecker's
/// test order share.

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "medspheres/robot_model.h"

namespace medspheres {

/// \p n joint vectors over \p joint_names (positions in that order), each entry uniform
/// within its joint's limits ([-pi, pi] for a continuous joint, one without limits or a
/// name \p model has no joint of), drawn in order from std::mt19937(seed): configuration
/// by configuration, joint by joint (the same vectors on every run of one build).
std::vector<Eigen::VectorXd> sample_configurations(const RobotModel& model,
                                                   const std::vector<std::string>& joint_names,
                                                   std::size_t n, unsigned seed);

/// The range sample_configurations draws joint \p name from: its limits, or [-pi, pi].
std::pair<double, double> sample_range(const RobotModel& model, const std::string& name);

}  // namespace medspheres
