#include "medspheres/sample_configurations.h"

#include <cmath>
#include <random>
#include <utility>

namespace medspheres {

std::vector<Eigen::VectorXd> sample_configurations(const RobotModel& model,
                                                   const std::vector<std::string>& joint_names,
                                                   std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::pair<double, double>> range;
  for (const std::string& name : joint_names) {
    const Joint* j = model.find_joint(name);
    const bool limited = j != nullptr && j->type != JointType::kContinuous && j->limits &&
                         j->limits->lower < j->limits->upper;
    range.emplace_back(limited ? j->limits->lower : -M_PI, limited ? j->limits->upper : M_PI);
  }
  std::vector<Eigen::VectorXd> out(n, Eigen::VectorXd(range.size()));
  for (Eigen::VectorXd& q : out)
    for (std::size_t k = 0; k < range.size(); ++k)
      q[k] = std::uniform_real_distribution<double>(range[k].first, range[k].second)(rng);
  return out;
}

}  // namespace medspheres
