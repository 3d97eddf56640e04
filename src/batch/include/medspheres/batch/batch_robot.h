#pragma once
/// \file
/// Baking robots from URDF files: one robot into its output folder (`medspheres robot
/// URDF -o DIR`), and many on the batch driver of batch.h (the same shards, jobs,
/// progress, rows and reports as meshes): each robot's files go to the folder of its
/// relative path without the extension (a/b/arm.urdf -> OUT/a/b/arm/), replaced as a
/// whole (write_robot_outputs), so a killed run leaves whole folders only.
///
/// Cache (robot_cache_key): content and relative layout only, so that a copy of the library
/// elsewhere is found: the SHA-256 of the URDF's bytes and its relative path, every mesh
/// file it references by its path relative to the URDF's folder (below that relative path)
/// with its SHA-256, every field of the job that changes the files (request, budget, outer
/// sets, from_visual, formats, set, the planner request with its SRDF's SHA-256, the
/// recorded options) and the tool's version. An entry is every output file in one
/// MessagePack map {"links", "spheres", "files": {name: bytes}}, written atomically, its
/// robot file naming the URDF and meshes by those relative paths; a copy from the entry
/// names them as read (the files are those a bake writes). An entry that does not read as
/// one is a miss and is overwritten by the next store.
///
/// Determinism: a batch bakes with request.record_seconds false, so the files carry no
/// times; a cached copy, a rerun and any split into shards give the same bytes.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/batch/batch.h"
#include "medspheres/formats/robot_outputs.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/contact_regions.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_bake/robot_planner_setup.h"

namespace medspheres {

/// What makes one robot's output folder from its URDF.
struct RobotJob {
  /// The bake (bake_robot); in a batch its jobs and progress are set by the batch, and
  /// its request is taken as a mesh batch takes one (no times, no progress, threads 0
  /// replaced by batch_threads_each).
  RobotBakeOptions bake;
  UrdfReadOptions read;
  std::vector<formats::SphereFormat> formats;  ///< empty: every robot format
  std::optional<formats::SphereChoice> set;    ///< none: robot_output_choice decides
  /// A JSON object recorded as the model's metadata "options" (how the run was asked
  /// for); empty: none.
  std::string options_json;
  /// Tool frames, self-collision matrix and default configuration (robot_planner_setup.h).
  PlannerRequest planner;
  /// Contact-aware covers (contact_regions.h: the covers baked again where the matrix's
  /// checked pairs come close); none: the covers of the first bake. Needs the matrix
  /// (planner.sample) and outer sets.
  std::optional<ContactOptions> contact;
};

struct RobotFileResult {
  RobotBakeResult bake;      ///< its model carries the planner setup
  SelfCollisionRun planner;  ///< the matrix's run (empty with planner.sample false)
  formats::SphereChoice choice = formats::SphereChoice::kInner;  ///< the planner formats' set
  std::size_t spheres = 0;            ///< of that set, all links (robot_spheres)
  std::vector<std::string> warnings;  ///< robot_warnings of the URDF read
};

/// Reads \p urdf (read_urdf), loads its meshes, bakes it (bake_robot) and replaces the
/// folder \p out with its files (write_robot_outputs).
/// \throws InputError as read_urdf, load_link_solids, bake_robot and the writers (naming
///   the URDF, the link and the problem), and (field "output") before any bake when \p out
///   holds the URDF, a mesh it names or the job's SRDF (check_output_spares_inputs); Error
///   when the folder cannot be replaced.
RobotFileResult bake_robot_file(const std::string& urdf, const std::string& out,
                                const RobotJob& job);

/// The output folder of a URDF, relative to the batch's output folder: its relative path
/// without the extension (a/b/arm.urdf -> a/b/arm).
std::string robot_output_relative(const std::string& relative);

/// 64 hex digits naming the files of \p robot (read from a URDF with SHA-256
/// \p urdf_sha256, whose path relative to the batch's folder is \p relative) made by
/// \p job (file comment).
/// \throws InputError naming the URDF and the link whose mesh file cannot be read.
std::string robot_cache_key(const UrdfRobot& robot, const std::string& urdf_sha256,
                            const RobotJob& job, const std::string& relative);

struct RobotBatchOptions : BatchSettings {
  RobotJob robot;  ///< every robot's; each bakes batch_threads_each(jobs) links at once
};

/// Bakes the URDFs of options.shard into their folders; rows as bake_batch, with links
/// (the robot's) and spheres (robot_spheres of the planner formats' set).
/// \throws as bake_batch.
BatchResult bake_robot_batch(const std::vector<BatchInput>& inputs,
                             const RobotBatchOptions& options);

}  // namespace medspheres
