#pragma once
/// \file
/// Contact-aware covers: where on each link the links it is checked against come close, so
/// that its cover can stick out less there (ProtrusionWeights, cover.h) and more elsewhere.
///
/// Regions. Over `samples` configurations within the joint limits (sample_configurations,
/// `seed`; the locked joints at their given positions), for every checked pair (a, b) of a
/// self-collision matrix (not ignored, both links with meshes): points of b's surface (its
/// meshes placed in its link frame, sampled every band / 2) that lie within `band` of a's
/// surface, expressed in a's link frame, join a's region; and the same with a and b
/// swapped. A link's region: those points, one per cell of band / 2 among the cells that
/// hold at least max(1, min_share x samples) of them. A surface
/// element of the link's cover within `band` of a region point is a contact element; the
/// balls that hold one stick out about 1 / `weight` as far as the others.
///
/// Bake (bake_contact_aware): the covers as bake_robot makes them; the matrix of the
/// request over them (make_planner_setup); the regions from its checked pairs; then every
/// link with a region baked again with its weights (RobotBakeOptions::outer_weights). The
/// planner setup of the result is computed again by the caller over the new covers. The
/// covers stay certified (the certificate is unchanged; only where the balls go differs).
/// Determinism: the same regions and spheres for every thread count.

#include <cstddef>
#include <map>
#include <string>

#include "medspheres/cover/protrusion_weights.h"
#include "medspheres/planner_setup.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_bake/robot_planner_setup.h"
#include "medspheres/robot_model.h"

namespace medspheres {

struct ContactOptions {
  std::size_t samples = 2000;  ///< configurations, >= 1
  unsigned seed = 2;           ///< of the configurations (not the matrix's own)
  double band = 0.02;          ///< metres, > 0
  double weight = 8.0;         ///< >= 1
  /// A region keeps the cells (of side band / 2) that partners' points fell in at least
  /// min_share x samples times (at least once): where partners come often. In [0, 1].
  double min_share = 0.0;
  int threads = 0;  ///< 0: all cores
};

/// \throws InputError naming the option (contact_samples, contact_band, contact_weight).
void validate(const ContactOptions& options);

/// Per link with a region (by name): its region's weights, points in the link frame.
/// \p matrix: the pairs; \p locked: joints held (actuated joints by name).
/// \throws InputError as validate(options), std::invalid_argument when \p solids do not
///   match the model's links.
std::map<std::string, ProtrusionWeights> contact_regions(
    const RobotModel& model, const std::vector<LinkSolid>& solids,
    const SelfCollisionMatrix& matrix, const std::map<std::string, double>& locked,
    const ContactOptions& options);

/// The two-pass bake of the file comment: bake_robot(robot, solids, bake), then the covers
/// of the links with a region baked again (\p first itself when \p planner computes no
/// matrix). \p first: the first pass's result. \p choice and
/// \p planner: what make_planner_setup is asked for (its matrix gives the pairs).
/// \throws as bake_robot, make_planner_setup and validate(contact).
RobotBakeResult rebake_contact_aware(const UrdfRobot& robot, const std::vector<LinkSolid>& solids,
                                     const RobotBakeOptions& bake, const RobotBakeResult& first,
                                     formats::SphereChoice choice, const PlannerRequest& planner,
                                     const ContactOptions& contact);

}  // namespace medspheres
