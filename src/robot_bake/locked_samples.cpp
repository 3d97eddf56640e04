// The matrix's random configurations (locked_samples.h).
#include "locked_samples.h"

#include <algorithm>

#include "medspheres/error.h"
#include "medspheres/fcl/robot_bounds.h"

namespace medspheres::detail {

std::vector<Eigen::VectorXd> locked_samples(const RobotModel& model, const KinematicTree& tree,
                                            const std::map<std::string, double>& locked,
                                            std::size_t samples, unsigned seed) {
  std::vector<Eigen::VectorXd> qs = fcl::sample_configurations(model, tree, samples, seed);
  const auto& names = tree.joint_names();
  for (const auto& [joint, q] : locked) {
    const auto it = std::find(names.begin(), names.end(), joint);
    if (it == names.end())
      throw InputError::option(ErrorKind::kOutOfRange, "locked_joints", joint,
                               "\"" + joint + "\" is no actuated joint of the robot");
    for (Eigen::VectorXd& s : qs) s[it - names.begin()] = q;
  }
  return qs;
}

}  // namespace medspheres::detail
