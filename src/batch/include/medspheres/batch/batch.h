#pragma once
/// \file
/// Baking many meshes in one call (the CLI's `bake` over several inputs): each input
/// through the bake pipeline (bake_mesh), outputs mirroring the inputs' relative paths
/// under an output folder, a shard of the inputs, an optional cache, inputs in parallel.
///
/// Files: each output is written atomically (write_file_atomically) as soon as its input
/// is done, so a killed run leaves whole files only, and with a cache a rerun bakes only
/// what the cache lacks. Outputs carry no wall-clock time (BakeRequest::record_seconds is
/// false) and name their mesh by its relative path, so an output is a pure function of
/// the mesh's bytes, its relative path, the request and the tool's version: a cached copy,
/// a rerun, and any split into shards give bit-identical files.
///
/// Failures: an input that fails (unreadable, malformed, no interior, an unreachable
/// budget, a failed write, ...) is a row with its error; the others go on.
///
/// Robots (batch_robot.h) go through the same driver: the same settings, rows and reports.

#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/batch/batch_inputs.h"
#include "medspheres/batch/batch_shard.h"
#include "medspheres/error.h"

namespace medspheres {

enum class BatchOutcome { kBaked, kCached, kFailed };

/// "baked", "cached", "failed".
const char* to_string(BatchOutcome outcome);

/// What a batch bakes: meshes (one sphere-set file each) or robots (one folder each).
enum class BatchItems { kMeshes, kRobots };

/// A robot's planner files, as `medspheres robot` summarises them (robot_planner_setup.h).
struct BatchPlannerSummary {
  std::string default_from;          ///< PlannerSetup::default_from
  std::size_t checked_pairs = 0;     ///< link pairs a planner checks (not ignored)
  std::size_t estimate_samples = 0;  ///< the estimate's other configurations (0: none made)
  std::size_t false_positives = 0;   ///< of them (SelfCollisionEstimate)
  std::size_t false_negatives = 0;   ///< of them (SelfCollisionEstimate)
};

/// One input's result.
struct BatchRow {
  BatchInput input;
  std::string output;  ///< what was written: output folder / the input's output name
  BatchOutcome outcome = BatchOutcome::kFailed;
  std::size_t links = 0;    ///< robots: the robot's links; 0 for meshes
  std::size_t spheres = 0;  ///< robots: of the set the planner formats carry, all links
  double nerr = std::numeric_limits<double>::quiet_NaN();  ///< as the file records it
  double seconds = 0.0;                                    ///< wall clock of this input
  std::string error;                      ///< what() of the failure; empty otherwise
  std::optional<InputError> input_error;  ///< the failure, when it is bad input
  std::vector<std::string> warnings;      ///< a baked mesh's loader's; a robot's for cuRobo
  /// Robots baked or copied with the self-collision matrix; none otherwise.
  std::optional<BatchPlannerSummary> planner;
};

/// Called once per finished input (one call at a time, from any thread): the row, and
/// how many of the shard's inputs are finished out of how many.
using BatchProgressFn =
    std::function<void(const BatchRow& row, std::size_t done, std::size_t total)>;

/// What every batch takes, of meshes or robots.
struct BatchSettings {
  std::string output_dir;  ///< created when missing
  std::string cache_dir;   ///< empty: no cache
  Shard shard;             ///< this call bakes the inputs in this shard only
  int jobs = 0;            ///< inputs baked at once, 1 to kMaxThreads; 0: one per core
  BatchProgressFn progress;
};

/// The threads each of \p jobs inputs baked at once gets: cores / jobs, at least 1.
int batch_threads_each(int jobs);

struct BatchOptions : BatchSettings {
  /// Every input's request; validated once before any work. medial.threads is each
  /// bake's thread count; 0 shares the cores among the jobs (batch_threads_each).
  /// medial.progress is not used; record_seconds is forced to false.
  BakeRequest request;
};

struct BatchResult {
  BatchItems items = BatchItems::kMeshes;
  std::vector<BatchRow> rows;    ///< the shard's inputs, in input order
  std::size_t other_shards = 0;  ///< inputs left to the other shards
  double seconds = 0.0;          ///< wall clock of the call
  std::size_t count(BatchOutcome outcome) const;
};

/// Bakes the inputs of options.shard.
/// \throws InputError as validate(request), naming output_dir or cache_dir when it
///   cannot be a folder, and naming both inputs when one's output is a folder that would
///   hold another's; std::invalid_argument for jobs outside [0, kMaxThreads]. Nothing
///   about one input throws.
BatchResult bake_batch(const std::vector<BatchInput>& inputs, const BatchOptions& options);

/// The rows as JSON: {"rows": [{"input", "relative", "output", "outcome", "spheres",
/// "nerr" (null when undefined or failed), "seconds", "error" (null when none)}, ...],
/// "totals": {"baked", "cached", "failed", "other_shards", "seconds"}}. Robots' rows
/// have "links" before "spheres" and no "nerr".
std::string batch_report_json(const BatchResult& result);

/// The rows as CSV (RFC 4180): a header "input,relative,output,outcome,spheres,nerr,
/// seconds,error" (robots: "input,relative,output,outcome,links,spheres,seconds,error"),
/// then one line per row (nerr and error empty when none).
std::string batch_report_csv(const BatchResult& result);

}  // namespace medspheres
