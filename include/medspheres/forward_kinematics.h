#pragma once
/// \file
/// Forward kinematics of a RobotModel: from joint positions to every link's pose.
///
/// Frames: W is the world. The root link's frame is X_WB, the base pose (identity unless
/// given). For a joint from parent P to child C at position q, X_WC = X_WP * X_PJ *
/// motion(q) (see robot_model.h): a rotation of q rad about the unit axis for revolute and
/// continuous joints, a translation of q m along it for prismatic ones, the identity for
/// fixed ones. Limits are not enforced. A mimic joint's position is multiplier * q_source
/// + offset, followed through chains of mimic joints.
///
/// Positions vector: one entry per *actuated* joint, i.e. the model's joints that are not
/// fixed and not mimic, in the model's (URDF) order; KinematicTree::joint_names() lists them.
/// Poses: one per link, in the model's link order.

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/robot_model.h"

namespace medspheres {

/// The kinematic tree of a validated model, with its walk order precomputed. Immutable
/// after construction: every const member is safe to call from many threads at once.
class KinematicTree {
 public:
  /// \throws InputError as validate_robot_model(model, source).
  explicit KinematicTree(const RobotModel& model, const std::string& source = "robot model");

  /// The actuated joints, in the order the positions vector uses.
  const std::vector<std::string>& joint_names() const noexcept { return actuated_names_; }
  /// The links, in the order of the returned poses (the model's order).
  const std::vector<std::string>& link_names() const noexcept { return link_names_; }
  std::size_t num_positions() const noexcept { return actuated_names_.size(); }

  /// The index of a link in link_names(). \throws std::invalid_argument naming it if unknown.
  std::size_t link_index(const std::string& link) const;

  /// X_WL of every link at positions \p q (radians for revolute and continuous joints,
  /// metres for prismatic ones).
  /// \throws std::invalid_argument when q.size() != num_positions() or an entry is not
  ///   finite (naming the joint).
  std::vector<Eigen::Isometry3d> link_poses(
      const Eigen::VectorXd& q,
      const Eigen::Isometry3d& X_WB = Eigen::Isometry3d::Identity()) const;

  /// The same, positions by joint name; actuated joints not in the map are at 0.
  /// \throws std::invalid_argument naming a joint that does not exist, is fixed or is a
  ///   mimic joint (set its source instead), or whose position is not finite.
  std::vector<Eigen::Isometry3d> link_poses(
      const std::map<std::string, double>& q,
      const Eigen::Isometry3d& X_WB = Eigen::Isometry3d::Identity()) const;

  /// One step of the walk: the child link's pose from its parent's, X_WC = X_WP * origin *
  /// motion(multiplier * q[source] + offset), as the file comment says.
  struct Step {
    std::size_t parent = 0, child = 0;  ///< link indices (link_names() order)
    JointType type = JointType::kFixed;
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< X_PJ
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           ///< unit
    long source = -1;  ///< index into q of the actuated joint driving it (-1: fixed)
    double multiplier = 1.0, offset = 0.0;  ///< q_joint = multiplier * q[source] + offset
  };
  /// The walk: parents before children, one step per joint (mimic chains resolved to their
  /// actuated source), for callers that pose many configurations their own way.
  const std::vector<Step>& steps() const noexcept { return steps_; }
  /// The root link's index in link_names().
  std::size_t root() const noexcept { return root_; }

 private:
  std::vector<std::string> link_names_;
  std::vector<std::string> actuated_names_;
  std::map<std::string, long> joint_kind_;  // every joint: its index in q, -1 fixed, -2 mimic
  std::size_t root_ = 0;
  std::vector<Step> steps_;  // parents before children
};

/// One-off forward kinematics: KinematicTree(model).link_poses(q, X_WB).
std::vector<Eigen::Isometry3d> forward_kinematics(
    const RobotModel& model, const Eigen::VectorXd& q,
    const Eigen::Isometry3d& X_WB = Eigen::Isometry3d::Identity());

}  // namespace medspheres
