#pragma once
// The driver every batch shares (meshes: batch.h, robots: batch_robot.h): the shard's
// rows, the output folder, the cache, the inputs run on a pool of jobs with progress; what
// one input is made into is the caller's.
#include <functional>
#include <string>
#include <vector>

#include "medspheres/batch/batch.h"

namespace medspheres {

class BakeCache;

struct BatchWork {
  BatchItems items = BatchItems::kMeshes;
  /// The output of an input, relative to the output folder, from its relative path.
  std::function<std::string(const std::string& relative)> output_relative;
  /// Makes row.output (whose folder exists) for row.input, from \p cache (null: none) or
  /// by baking; sets the outcome (baked or cached) and the counts. Throws on failure: the
  /// driver makes the row a failed one with the error.
  std::function<void(BatchRow& row, const BakeCache* cache)> run;
};

/// \p request as every input of a batch bakes it: no times recorded, no progress, and
/// medial.threads 0 replaced by batch_threads_each(jobs); validated.
/// \throws as validate(request) and check_threads(jobs).
BakeRequest batch_request(BakeRequest request, int jobs);

/// The rows of \p settings.shard, each run by \p work.run, \p settings.jobs at a time.
/// \throws as bake_batch, but for the request.
BatchResult run_batch(const std::vector<BatchInput>& inputs, const BatchSettings& settings,
                      const BatchWork& work);

}  // namespace medspheres
