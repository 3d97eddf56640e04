#pragma once
// The random configurations of the self-collision matrix and its estimate: each actuated
// joint uniform within its limits (fcl::sample_configurations), the locked joints held.

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "medspheres/forward_kinematics.h"
#include "medspheres/robot_model.h"

namespace medspheres::detail {

/// \p samples configurations (KinematicTree order) drawn with \p seed, each joint of
/// \p locked at its position.
/// \throws InputError (option "locked_joints") naming a locked joint that is no actuated
///   joint of the robot.
std::vector<Eigen::VectorXd> locked_samples(const RobotModel& model, const KinematicTree& tree,
                                            const std::map<std::string, double>& locked,
                                            std::size_t samples, unsigned seed);

}  // namespace medspheres::detail
