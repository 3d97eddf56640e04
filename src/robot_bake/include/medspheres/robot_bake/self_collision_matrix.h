#pragma once
/// \file
/// The self-collision matrix of a robot, computed as MoveIt's setup assistant computes an
/// SRDF's disable_collisions, and the default configuration a planner starts from.
///
/// Samples: `samples` configurations, each actuated joint uniform within its limits
/// ([-pi, pi] for a continuous joint or one without limits; fcl::sample_configurations with
/// `seed`), the locked joints at their given positions. Every pair of links that the planner
/// files carry spheres for is classified (planner_setup.h's PairClass), first class that
/// applies:
/// 1. given: disabled by a given SRDF: skipped, not sampled;
/// 2. adjacent: their rigid bodies joined by a joint (adjacent_link_pairs: bodies without
///    spheres between them skipped), or one rigid body (fixed joints only) with their solids
///    within `margin`: skipped;
/// 3. always: the solids collide (touch) in at least `threshold` of the samples: skipped;
/// 4. never: the solids never came within `margin` in any sample (a rigid pair apart), and a
///    search for a contact from the two samples where the links' covering balls come nearest
///    found none (contact_search.h: the joints between the two links moved to deepen their
///    planner spheres' overlap; a contact found makes the pair checked): skipped;
/// 5. sphere_only: the solids never collided, the planner's spheres did, and the search from
///    the samples where the solids first came near and the spheres first touched found no
///    contact: skipped;
/// 6. default: the solids collide at the zero pose clamped into the limits: checked;
/// 7. checked: the rest (the solids collide in some samples, or come within the margin
///    while the planner's spheres never collide): checked.
/// A pair whose solids collide in a sample is never skipped unless it is adjacent, given or
/// always colliding. On a robot whose tree is its own mirror image by its links' names
/// (left and right swapped: mirror_links.h), a pair that would be skipped as never or
/// sphere_only is checked when its mirror image is checked and was seen colliding: the
/// samples missed a contact that its twin shows (SelfCollisionRun::mirrored counts them).
///
/// Default configuration: the zero pose clamped into the limits when no checked pair's
/// spheres touch there ("zero"); else the nearest configuration (Euclidean in joint values)
/// where none does among the samples and the points 1/16, 1/8, 1/4 and 1/2 of the way from
/// the zero pose to each ("sample": within the limits, the locked joints held); else the
/// zero pose with self-collision buffers ("zero_buffered"): each link of a checked pair whose
/// spheres touch there gets a buffer of minus half that pair's deepest overlap and 0.1 mm
/// (the least of them over its pairs), which shrinks its spheres for self-collision only.
/// The buffers are 0 otherwise: a negative buffer shrinks a covering set, and a pair that
/// touches could then go unseen (the trade-off is stated in docs/self-collision.md). Should
/// pairs still touch ("zero_not_free"), SelfCollisionRun::default_pairs names them.
///
/// Exactness: the solids' verdicts are certified (LinkSolids: sphere bounds, then FCL's
/// exact mesh distance); only the samples are random. A pair is evaluated only as long as a
/// sample could still change its class (a pair seen colliding, seen within the margin and
/// past the `always` threshold is done), so classes match a full evaluation of every sample.
/// Threads: pairs in parallel (`threads`, 0: all cores); the result does not depend on it.

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "medspheres/formats/robot_spheres.h"
#include "medspheres/formats/srdf_disabled_collisions.h"
#include "medspheres/planner_setup.h"
#include "medspheres/robot_bake/link_collision_geometry.h"
#include "medspheres/robot_bake/self_collision_estimate.h"
#include "medspheres/robot_model.h"

namespace medspheres {

struct SelfCollisionOptions {
  std::size_t samples = 10000;  ///< configurations sampled, >= 1
  unsigned seed = 1;            ///< of the samples
  double threshold = 0.95;      ///< share of samples for "always", in (0, 1] (MoveIt's default)
  double margin = 0.01;         ///< metres, >= 0: "never" beyond it
  int threads = 0;              ///< pairs at once, 0 to kMaxThreads (0: all cores)
  bool search = true;           ///< never and sphere_only pairs searched for a contact
  /// Configurations of the estimate (self_collision_estimate.h; 0: none), drawn with seed +
  /// 7919: made by make_planner_setup for a caller that asks for the run, unless the matrix
  /// checks no pair. It changes no file.
  std::size_t estimate = 10000;
};

/// \throws InputError naming the option (samples, threshold, margin, threads) out of range.
void validate(const SelfCollisionOptions& options);

/// \throws InputError (option "srdf") naming a disabled pair's link that \p model lacks.
void check_disabled_pairs(const RobotModel& model,
                          const std::vector<formats::DisabledCollision>& given);

struct SelfCollisionRun {
  SelfCollisionMatrix matrix;                       ///< every pair, buffers 0
  std::map<std::string, double> default_positions;  ///< every actuated joint
  std::string default_from;                         ///< "zero", "sample" or "zero_not_free"
  /// Checked pairs whose spheres touch at the default configuration, the buffers applied
  /// (empty unless default_from is "zero_not_free").
  std::vector<std::pair<std::string, std::string>> default_pairs;
  std::size_t mirrored = 0;  ///< pairs checked as their mirror images (file comment)
  /// Pairs checked by the search for a contact (file comment, classes 4 and 5): each with
  /// the configuration (KinematicTree order) where their solids touch.
  std::map<std::pair<std::string, std::string>, Eigen::VectorXd> contacts;
  double seconds = 0.0;          ///< wall clock
  SolidQueryCounts solids;       ///< the exact side's work
  std::size_t sphere_tests = 0;  ///< the planner's spheres, pair by pair
  /// The matrix's false positives and negatives over other configurations
  /// (SelfCollisionOptions::estimate of them; 0 samples when none was made: compute_self_collision
  /// leaves it so, make_planner_setup fills it).
  SelfCollisionEstimate estimate;
  double estimate_seconds = 0.0;  ///< wall clock
};

/// The matrix of \p model's links over the planner's spheres \p carried, with the solids
/// \p solids, the joints \p locked held at their positions (actuated joints by name), and the
/// pairs \p given taken as disabled.
/// \throws InputError naming the option, or a given pair's or locked joint's unknown name.
SelfCollisionRun compute_self_collision(const RobotModel& model, const LinkSolids& solids,
                                        const formats::RobotSpheres& carried,
                                        const std::map<std::string, double>& locked,
                                        const std::vector<formats::DisabledCollision>& given,
                                        const SelfCollisionOptions& options);

}  // namespace medspheres
