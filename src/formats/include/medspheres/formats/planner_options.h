#pragma once
/// \file
/// The planner keys of the cuRobo, XRDF and SRDF files of a robot model: its PlannerSetup
/// (planner_setup.h; the default one when the model has none), restricted to the links of
/// the spheres written.
/// - tool frames: listed_tool_frames (the chosen ones first);
/// - self_collision_ignore: the matrix's skipped pairs whose two links both have spheres,
///   keyed by the first link, both in model link order;
/// - self_collision_buffer: every link with spheres (0 where the matrix has none);
/// - when every pair is skipped, one pair is left out of the ignore lists, made unable to
///   touch by a negative buffer (cuRobo's loaders divide by the number of checked pairs);
/// - cspace: every actuated joint at its default position; cuRobo's lock_joints and the
///   joints XRDF's cspace leaves out are the setup's locked joints;
/// - SRDF: one <disable_collisions> per skipped pair, with its reason (srdf_reason).

#include <cstddef>
#include <string>
#include <vector>

#include "medspheres/formats/curobo_yaml.h"
#include "medspheres/formats/robot_spheres.h"
#include "medspheres/formats/srdf_disabled_collisions.h"
#include "medspheres/formats/xrdf.h"
#include "medspheres/planner_setup.h"
#include "medspheres/robot_model.h"

namespace medspheres::formats {

/// The model's setup, or the default one for the links of \p spheres.
PlannerSetup planner_setup_for(const RobotModel& model, const RobotSpheres& spheres);

/// cuRobo's options in \p layout; \p urdf_path is written as urdf_path when not empty.
CuroboOptions curobo_options(const RobotModel& model, const RobotSpheres& spheres,
                             CuroboLayout layout, const std::string& urdf_path);

/// The sphere pairs cuRobo checks for self-collision with the cuRobo options of \p model
/// over \p spheres: every sphere of a link against every sphere of each other link that
/// their self_collision_ignore does not skip. cuRobo's work grows with it; v1's faster
/// kernel takes at most kCuroboV1FastPairs.
std::size_t curobo_sphere_pairs(const RobotModel& model, const RobotSpheres& spheres);

/// The sphere pairs cuRobo v1's faster self-collision kernel takes (32 x 512); beyond, v1
/// warns and runs its slower one.
inline constexpr std::size_t kCuroboV1FastPairs = 32 * 512;

XrdfOptions xrdf_options(const RobotModel& model, const RobotSpheres& spheres);

/// The skipped pairs (every one, links with spheres or not), with their reasons.
std::vector<DisabledCollision> srdf_disabled_pairs(const RobotModel& model,
                                                   const RobotSpheres& spheres);

}  // namespace medspheres::formats
