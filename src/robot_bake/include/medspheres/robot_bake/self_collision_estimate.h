#pragma once
/// \file
/// What the planner files' self-collision checks report against the links' exact solids,
/// over random configurations other than the matrix's samples: how often a planner would
/// see the robot in self-collision where it is not (false positives), and where it would
/// miss one (false negatives; none with covering sets).
///
/// Configurations: `samples` drawn as the matrix draws its own (each actuated joint uniform
/// within its limits, the locked joints held), with the seed `seed`. In each:
/// - the checked pairs (the matrix's pairs not ignored) whose spheres touch, with the
///   matrix's buffers (PlannerSpheres, as cuRobo checks them);
/// - the judged pairs (every pair but the adjacent and always-colliding ones, whose solids
///   are taken to touch) whose solids touch (LinkSolids, certified).
/// A false positive: some checked pair's spheres touch and no judged pair's solids do. A
/// false negative: some checked pair's solids touch and no checked pair's spheres do.
/// bench_self_collision counts the same over its own configurations (`FP cfg`, `FN cfg`).
/// Threads: configurations in parallel (0: all cores); the counts do not depend on it.

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "medspheres/formats/robot_spheres.h"
#include "medspheres/planner_setup.h"
#include "medspheres/robot_bake/link_collision_geometry.h"
#include "medspheres/robot_model.h"

namespace medspheres {

struct SelfCollisionEstimate {
  std::size_t samples = 0;          ///< configurations drawn
  unsigned seed = 0;                ///< of the configurations
  std::size_t false_positives = 0;  ///< configurations (file comment)
  std::size_t false_negatives = 0;  ///< configurations (file comment)
  /// Per checked pair (link1, link2) that alone makes false positives: how many; most
  /// first (ties in the matrix's order).
  std::vector<std::pair<std::pair<std::string, std::string>, std::size_t>> alone;
};

/// The estimate of \p matrix (computed for \p model, whose solids are \p solids and whose
/// planner files carry \p carried), the joints \p locked held at their positions.
/// \throws InputError naming a locked joint that is no actuated joint of the robot, or a
///   link of the matrix or of \p carried that the robot lacks.
SelfCollisionEstimate estimate_self_collision(const RobotModel& model, const LinkSolids& solids,
                                              const formats::RobotSpheres& carried,
                                              const SelfCollisionMatrix& matrix,
                                              const std::map<std::string, double>& locked,
                                              std::size_t samples, unsigned seed, int threads);

}  // namespace medspheres
