#include "medspheres/forward_kinematics.h"

#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace medspheres {

namespace {

constexpr long kFixedJoint = -1;
constexpr long kMimicJoint = -2;

// The rotation by angle q about the unit axis u (Rodrigues' formula).
Eigen::Matrix3d rotation(const Eigen::Vector3d& u, double q) {
  const double c = std::cos(q), s = std::sin(q), t = 1.0 - c;
  Eigen::Matrix3d r;
  r << t * u.x() * u.x() + c, t * u.x() * u.y() - s * u.z(), t * u.x() * u.z() + s * u.y(),
      t * u.x() * u.y() + s * u.z(), t * u.y() * u.y() + c, t * u.y() * u.z() - s * u.x(),
      t * u.x() * u.z() - s * u.y(), t * u.y() * u.z() + s * u.x(), t * u.z() * u.z() + c;
  return r;
}

// X_WC = X_WP X_PJ X_JC(q), the joint's motion X_JC a rotation about, or a translation
// along, its axis; written out so that no 4 x 4 product is formed.
void step_pose(const Eigen::Isometry3d& X_WP, const Eigen::Isometry3d& X_PJ, JointType type,
               const Eigen::Vector3d& axis, double q, Eigen::Isometry3d& X_WC) {
  const Eigen::Matrix3d R_WJ = X_WP.linear() * X_PJ.linear();
  X_WC.translation() = X_WP.linear() * X_PJ.translation() + X_WP.translation();
  switch (type) {
    case JointType::kRevolute:
    case JointType::kContinuous:
      X_WC.linear() = R_WJ * rotation(axis, q);
      break;
    case JointType::kPrismatic:
      X_WC.translation() += R_WJ * (q * axis);
      X_WC.linear() = R_WJ;
      break;
    case JointType::kFixed:
      X_WC.linear() = R_WJ;
      break;
  }
}

}  // namespace

KinematicTree::KinematicTree(const RobotModel& model, const std::string& source) {
  validate_robot_model(model, source);
  std::unordered_map<std::string, std::size_t> link_at;
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    link_names_.push_back(model.links[i].name);
    link_at[model.links[i].name] = i;
  }
  for (const Joint& j : model.joints) {
    long kind = kFixedJoint;
    if (j.mimic) {
      kind = kMimicJoint;
    } else if (j.type != JointType::kFixed) {
      kind = static_cast<long>(actuated_names_.size());
      actuated_names_.push_back(j.name);
    }
    joint_kind_[j.name] = kind;
  }

  // Walk order: breadth first from the root, children in joint order.
  std::unordered_map<std::string, std::vector<const Joint*>> children;
  std::unordered_map<std::string, bool> is_child;
  for (const Joint& j : model.joints) {
    children[j.parent].push_back(&j);
    is_child[j.child] = true;
  }
  for (std::size_t i = 0; i < model.links.size(); ++i)
    if (!is_child.count(model.links[i].name)) root_ = i;
  std::vector<std::string> queue{link_names_[root_]};
  for (std::size_t head = 0; head < queue.size(); ++head) {
    for (const Joint* j : children[queue[head]]) {
      Step s;
      s.parent = link_at.at(j->parent);
      s.child = link_at.at(j->child);
      s.type = j->type;
      s.origin = j->origin;
      if (j->type != JointType::kFixed) s.axis = j->axis.normalized();
      // Follow mimic sources to the actuated joint, composing the affine maps:
      // q = m1 (m2 q_s + o2) + o1 = (m1 m2) q_s + (m1 o2 + o1).
      const Joint* at = j;
      while (at->mimic) {
        s.offset += s.multiplier * at->mimic->offset;
        s.multiplier *= at->mimic->multiplier;
        at = model.find_joint(at->mimic->joint);
      }
      s.source = joint_kind_.at(at->name);
      steps_.push_back(s);
      queue.push_back(j->child);
    }
  }
}

std::size_t KinematicTree::link_index(const std::string& link) const {
  for (std::size_t i = 0; i < link_names_.size(); ++i)
    if (link_names_[i] == link) return i;
  throw std::invalid_argument("forward kinematics: no link named \"" + link + "\"");
}

std::vector<Eigen::Isometry3d> KinematicTree::link_poses(const Eigen::VectorXd& q,
                                                         const Eigen::Isometry3d& X_WB) const {
  if (static_cast<std::size_t>(q.size()) != actuated_names_.size())
    throw std::invalid_argument("forward kinematics: " + std::to_string(q.size()) +
                                " joint positions given, the robot has " +
                                std::to_string(actuated_names_.size()) + " actuated joints");
  for (std::size_t i = 0; i < actuated_names_.size(); ++i)
    if (!std::isfinite(q[static_cast<Eigen::Index>(i)]))
      throw std::invalid_argument("forward kinematics: the position of joint \"" +
                                  actuated_names_[i] + "\" is not finite");
  std::vector<Eigen::Isometry3d> X_WL(link_names_.size(), Eigen::Isometry3d::Identity());
  X_WL[root_] = X_WB;
  for (const Step& s : steps_) {
    const double qj = s.source < 0 ? 0.0 : s.multiplier * q[s.source] + s.offset;
    step_pose(X_WL[s.parent], s.origin, s.type, s.axis, qj, X_WL[s.child]);
  }
  return X_WL;
}

std::vector<Eigen::Isometry3d> KinematicTree::link_poses(const std::map<std::string, double>& q,
                                                         const Eigen::Isometry3d& X_WB) const {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(actuated_names_.size()));
  for (const auto& [name, value] : q) {
    const auto it = joint_kind_.find(name);
    if (it == joint_kind_.end())
      throw std::invalid_argument("forward kinematics: no joint named \"" + name + "\"");
    if (it->second == kFixedJoint)
      throw std::invalid_argument("forward kinematics: joint \"" + name + "\" is fixed");
    if (it->second == kMimicJoint)
      throw std::invalid_argument("forward kinematics: joint \"" + name +
                                  "\" is a mimic joint; set the joint it mimics instead");
    v[it->second] = value;
  }
  return link_poses(v, X_WB);
}

std::vector<Eigen::Isometry3d> forward_kinematics(const RobotModel& model, const Eigen::VectorXd& q,
                                                  const Eigen::Isometry3d& X_WB) {
  return KinematicTree(model).link_poses(q, X_WB);
}

}  // namespace medspheres
