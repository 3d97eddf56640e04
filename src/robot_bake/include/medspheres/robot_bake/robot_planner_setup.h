#pragma once
/// \file
/// A baked robot's PlannerSetup (planner_setup.h), what `medspheres robot` and Python's
/// bake_robot write into every planner file:
/// - tool frames: the request's when given; else an SRDF's end effectors (their
///   parent_link) when one is given and names any; else default_tool_frames;
/// - locked joints: finger_joints of the tool frames, held at the zero pose clamped into
///   their limits;
/// - the self-collision matrix and default configuration (self_collision_matrix.h), over the
///   set the planner files carry, with an SRDF's disabled pairs taken as given; or, with
///   `sample` false, only adjacent pairs skipped and the zero pose clamped (not checked).

#include <string>
#include <vector>

#include "medspheres/formats/robot_spheres.h"
#include "medspheres/planner_setup.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot_bake/self_collision_matrix.h"
#include "medspheres/robot_model.h"

namespace medspheres {

struct PlannerRequest {
  std::vector<std::string> tool_frames;  ///< links of the robot; empty: SRDF's or default
  std::string srdf;                      ///< an SRDF file; empty: none
  /// Joints the planner files leave free although the rules lock them (a hand's finger
  /// joints, for in-hand planning); each an actuated finger joint below the tool frames.
  std::vector<std::string> free_joints;
  bool sample = true;  ///< compute the matrix (false: adjacency only)
  SelfCollisionOptions self_collision;
};

/// The request as text, one field per line: what changes the files (a cache key's part).
std::string planner_request_text(const PlannerRequest& request);

/// Checks \p request against \p model (its links and joints; no spheres needed) before any
/// work: the options' ranges, the tool frames, the free joints (actuated joints that the
/// rules lock), the SRDF (readable; its end effectors and disabled pairs name links of the robot).
/// \throws InputError as make_planner_setup.
void check_planner_request(const RobotModel& model, const PlannerRequest& request);

/// The setup of \p model (baked, with its spheres) whose solids are \p solids, for the planner
/// files' set \p carried. With \p run, the matrix's run, and its estimate
/// (self_collision_estimate.h) unless request.self_collision.estimate is 0 or no pair is
/// checked.
/// \throws InputError naming the option: a tool frame that is no link of the robot, a free
///   joint that is no actuated joint of it or that the rules do not lock, an SRDF that
///   cannot be read or names unknown links, options out of range.
PlannerSetup make_planner_setup(const RobotModel& model, const std::vector<LinkSolid>& solids,
                                formats::SphereChoice carried, const PlannerRequest& request,
                                SelfCollisionRun* run = nullptr);

}  // namespace medspheres
