#include "medspheres/sample_configurations.h"

#include <cmath>
#include <random>
#include <utility>

namespace medspheres {

std::pair<double, double> sample_range(const RobotModel& model, const std::string& name) {
  const Joint* j = model.find_joint(name);
  const bool limited = j != nullptr && j->type != JointType::kContinuous && j->limits &&
                       j->limits->lower < j->limits->upper;
  return {limited ? j->limits->lower : -M_PI, limited ? j->limits->upper : M_PI};
}

std::vector<Eigen::VectorXd> sample_configurations(const RobotModel& model,
                                                   const std::vector<std::string>& joint_names,
                                                   std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::pair<double, double>> range;
  for (const std::string& name : joint_names) range.push_back(sample_range(model, name));
  std::vector<Eigen::VectorXd> out(n, Eigen::VectorXd(range.size()));
  for (Eigen::VectorXd& q : out)
    for (std::size_t k = 0; k < range.size(); ++k)
      q[k] = std::uniform_real_distribution<double>(range[k].first, range[k].second)(rng);
  return out;
}

}  // namespace medspheres
