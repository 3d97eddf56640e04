#pragma once
// A search for a contact that a pair's samples missed: the self-collision matrix's pairs that
// its samples would skip (never, sphere_only) are searched before they are skipped
// (self_collision_matrix.h). Private to the robot_bake target.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "medspheres/forward_kinematics.h"
#include "medspheres/robot_bake/link_collision_geometry.h"
#include "medspheres/robot_model.h"

namespace medspheres::detail {

/// What a search reads: the robot, its tree, its links' exact solids and the planner's
/// spheres, and the joints held at their positions.
struct ContactSearchRobot {
  const RobotModel& model;
  const KinematicTree& tree;
  const LinkSolids& solids;
  const PlannerSpheres& carried;
  const std::map<std::string, double>& locked;
};

/// Climbs from each of \p starts (configurations in the tree's order) to a deeper overlap of
/// the planner's spheres of links \p a and \p b, moving only the actuated joints on the tree's
/// path between them (not locked ones), each within its sampled range
/// (sample_configurations.h), a seeded Gaussian step that shrinks as steps fail; returns the
/// first configuration on the way where their solids touch (certified: LinkSolids::within),
/// or none. Deterministic for a \p seed.
std::optional<Eigen::VectorXd> search_contact(const ContactSearchRobot& r, std::size_t a,
                                              std::size_t b,
                                              const std::vector<Eigen::VectorXd>& starts,
                                              unsigned seed, SolidQueryCounts& counts);

}  // namespace medspheres::detail
