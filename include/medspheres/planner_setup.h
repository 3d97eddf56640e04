#pragma once
/// \file
/// PlannerSetup: what a motion planner needs beside the spheres, as plain data that the
/// robot file carries and every planner format writes:
/// - the tool frames (cuRobo's tool_frames, its older ee_link; the first is the primary);
/// - the joints held fixed while planning (the tool frames' finger joints: cuRobo's
///   lock_joints) and a default configuration (cuRobo's default_joint_position or
///   retract_config, XRDF's default_joint_positions);
/// - the self-collision matrix: every pair of links with spheres, its class and whether a
///   planner skips it (cuRobo's self_collision_ignore, XRDF's self_collision: ignore, an
///   SRDF's disable_collisions with its reason), and per link the self-collision buffer
///   (cuRobo's self_collision_buffer, XRDF's self_collision: buffer_distance; metres, added
///   to every sphere radius of the link in self-collision checks only).
///
/// The robot bake computes it (medspheres/robot_bake/self_collision_matrix.h); a model without one
/// gets planner_setup_or_default(): the tool frames by default_tool_frames, the zero pose
/// clamped into the limits, and only adjacent pairs skipped.
///
/// Frames and units: joint positions in radians (revolute, continuous) or metres
/// (prismatic), by joint name; buffers in metres.

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace medspheres {

struct RobotModel;

/// How the self-collision matrix classified a pair of links. The meshes are the links' exact
/// solids; the spheres are the set the planner files carry.
enum class PairClass {
  /// Joined by a joint (adjacent_link_pairs), or rigidly joined (fixed joints only) with
  /// their meshes within the margin: skipped.
  kAdjacent,
  /// The meshes collide in at least `threshold` of the samples: skipped.
  kAlways,
  /// The meshes never came within `margin` of each other in any sample (or are rigidly
  /// joined and apart): skipped.
  kNever,
  /// The meshes never collided in any sample but the spheres did: an artefact of covering at
  /// this budget: skipped.
  kSphereOnly,
  /// The meshes collide at the zero pose clamped into the limits, and not always: checked,
  /// and the default configuration is moved off the zero pose.
  kDefault,
  /// The meshes collide in some samples, or come within the margin while the spheres never
  /// collide: checked.
  kChecked,
  /// Disabled by a given SRDF (its reason kept): skipped.
  kGiven,
};

/// "adjacent", "always", "never", "sphere_only", "default", "checked", "given".
const char* pair_class_name(PairClass kind);
/// The class named \p name, or nullopt.
std::optional<PairClass> parse_pair_class(const std::string& name);
/// The reason an SRDF's <disable_collisions> gives for a skipped pair of this class, in
/// MoveIt's setup assistant's words: "Adjacent", "Always", "Never" (kNever and kSphereOnly:
/// the meshes never collided); "" for a checked class.
const char* srdf_reason(PairClass kind);

/// One pair of links, link1 before link2 in the model's link order.
struct LinkPairClass {
  std::string link1;
  std::string link2;
  PairClass kind = PairClass::kChecked;
  bool ignored = false;  ///< a planner skips it
  std::string reason;    ///< kGiven: the SRDF's reason attribute as written
};

struct SelfCollisionMatrix {
  /// Every pair of links with spheres, in model order (link1's index, then link2's).
  std::vector<LinkPairClass> pairs;
  /// Per link with spheres: the self-collision buffer, metres (0: the spheres as written).
  std::map<std::string, double> buffer;
  std::size_t samples = 0;  ///< configurations sampled (0: not computed, e.g. adjacency only)
  unsigned seed = 0;        ///< of the samples
  double threshold = 0.0;   ///< share of samples for kAlways
  double margin = 0.0;      ///< metres, for kNever
  std::string srdf;         ///< the SRDF whose pairs were taken as given; empty when none
};

struct PlannerSetup {
  /// Links whose poses a planner reports; the first is the primary end effector.
  std::vector<std::string> tool_frames;
  /// How they were chosen: "option" (given), "srdf" (an SRDF's end effectors), "gripper" (the
  /// link that carries a gripper or hand, per branch), "frame" (a tool frame by its name), "branch"
  /// (the last moving link of a branch), "root" (a robot without moving joints).
  std::string tool_frames_from;
  /// Actuated joints held at their default position while planning (cuRobo's lock_joints).
  std::vector<std::string> locked_joints;
  /// Every actuated joint's default position (KinematicTree::joint_names).
  std::map<std::string, double> default_positions;
  /// "zero" (the zero pose clamped into the limits, free), "sample" (the free configuration
  /// nearest to it among the matrix's samples and points on the way to them), "zero_buffered"
  /// (the zero pose clamped, free with the matrix's self-collision buffers), "zero_not_free"
  /// (no free configuration was found; the zero pose clamped), "zero_unchecked" (the zero
  /// pose clamped, freedom not checked: no matrix computed).
  std::string default_from;
  std::optional<SelfCollisionMatrix> self_collision;
};

/// Per branch, the link a planner reports: the carrier of a gripper or hand below the branch's end
/// (the last link moved by a joint that is not a finger's: docs/self-collision.md), else a frame
/// fixed to that end named as a tool frame is (tool0, tool_frame, tcp, ...), else the end itself.
/// A carrier: the first link with two or more finger joints among its child joints (the jaws; a
/// prismatic joint above them stays the arm's), else the first rigidly attached with one. Grippers
/// first, then the ends with the most moving joints above them (an arm's before a head's or a
/// leg's), then link order. \p from: "gripper", "frame", "branch" or "root" (the first's
/// reason).
std::vector<std::string> default_tool_frames(const RobotModel& model, std::string* from = nullptr);

/// The finger joints (prismatic, mimic, a hand's) that move links below \p tool_frames without
/// any other moving joint between: the gripper's own joints, held at their default while
/// planning. Only actuated joints (not mimic ones), in model joint order. None when they would
/// be every actuated joint (a hand or a gripper alone, whose fingers a planner moves).
std::vector<std::string> finger_joints(const RobotModel& model,
                                       const std::vector<std::string>& tool_frames);

/// Each actuated joint at 0, clamped into its limits when it has some (lower < upper).
std::map<std::string, double> clamped_zero(const RobotModel& model);

/// Each link's rigid body, as the index of the body's first link in model order: links
/// joined by fixed joints move as one.
std::vector<std::size_t> rigid_bodies(const RobotModel& model);

/// Pairs of links with geometry (has_geometry[i] for model.links[i]) joined by a joint, links
/// without geometry between them skipped (as MoveIt's setup assistant skips them): from each
/// link with geometry that no link with geometry carries rigidly (through fixed joints
/// above it), across the moving joint above its rigid body, up to the nearest link with
/// geometry; or to a link without geometry whose rigid body has some, whose links with
/// geometry then stand for it (a robot's pelvis frame and the pelvis shell fixed to it).
/// As (a, b) indices into model.links, a < b, sorted.
std::vector<std::pair<std::size_t, std::size_t>> adjacent_link_pairs(
    const RobotModel& model, const std::vector<bool>& has_geometry);

/// Pairs of links with geometry in one rigid body (their relative pose never changes: a
/// planner has nothing to check), as (a, b), a < b, sorted.
std::vector<std::pair<std::size_t, std::size_t>> rigid_link_pairs(
    const RobotModel& model, const std::vector<bool>& has_geometry);

/// The model's setup, or when it has none the default: default_tool_frames, their finger
/// joints locked, clamped_zero, and a matrix (samples 0) over the links with spheres
/// (has_spheres[i] for model.links[i]) that skips the adjacent and the rigid pairs (both as
/// class adjacent).
PlannerSetup planner_setup_or_default(const RobotModel& model,
                                      const std::vector<bool>& has_spheres);

/// The links a planner file lists as tool frames: \p tool_frames, then, for every actuated
/// joint that no path from the root to a tool frame or to a link with spheres crosses, the
/// lowest such joint's child link, so that every actuated joint is in cuRobo's kinematic
/// tree (its loaders build the tree from those links; cuRobo v1 cannot lock a joint outside
/// it). In model link order after \p tool_frames.
std::vector<std::string> listed_tool_frames(const RobotModel& model,
                                            const std::vector<std::string>& tool_frames,
                                            const std::vector<bool>& has_spheres);

/// PlannerSetup::tool_frames_from and default_from in words, for summaries and reports
/// ("per branch, the link that carries the gripper"); the text itself when unknown.
std::string tool_frames_from_text(const std::string& from);
std::string default_from_text(const std::string& from);

/// The pairs a planner skips, (link1, link2) as the matrix lists them.
std::vector<std::pair<std::string, std::string>> ignored_pairs(const SelfCollisionMatrix& m);

/// Checks \p setup against \p model: tool frames, locked joints and default positions name
/// links and actuated joints of the model (every actuated joint has a finite default);
/// pairs name two different links, none twice; buffers are finite and name links;
/// threshold in [0, 1], margin finite and >= 0.
/// \throws InputError "<source>: planner: ..." naming the link, joint or pair.
void validate_planner_setup(const RobotModel& model, const PlannerSetup& setup,
                            const std::string& source);

}  // namespace medspheres
