#pragma once
// `medspheres bake` over many inputs: the flags, and the run that prints its progress,
// summary and report.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "medspheres/bake/bake_pipeline.h"

namespace medspheres::cli {

struct BatchFlags {
  std::string from_list;  ///< a list file, or "-" for standard input
  int jobs = 0;
  std::string shard;
  std::string cache;
  std::string report;
  std::vector<std::string> extensions;
  std::string relative_to;
};

/// Registers --from-list, --jobs, --shard, --cache, --report, --ext and --relative-to.
void add_batch_flags(CLI::App& sub, BatchFlags& flags);

/// A batch is several inputs, a folder, a list, or any batch flag.
bool is_batch(const std::vector<std::string>& inputs, const BatchFlags& flags);

/// Bakes the inputs into the folder \p out with the validated \p request; exit 0 when
/// every input of the shard is baked or cached, 2 when some failed on bad input only, 1
/// when some failed otherwise.
int run_batch(const std::vector<std::string>& inputs, const std::string& out,
              const BatchFlags& flags, const BakeRequest& request, bool quiet);

}  // namespace medspheres::cli
