#pragma once
// `medspheres bake` and `medspheres robot` over many inputs: the flags, and the run that
// prints its progress, summary and report.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "medspheres/batch/batch.h"

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

/// What a command's batch bakes: its inputs' name, the help of its flags, the library call.
struct BatchCommand {
  const char* noun = "mesh";            ///< "mesh", "robot"
  std::string jobs_help;                ///< --jobs
  std::string extensions_help;          ///< --ext
  std::vector<std::string> extensions;  ///< what a folder is scanned for without --ext
  bool jobs_make_a_batch = true;        ///< --jobs alone makes one input a batch
  std::function<BatchResult(const std::vector<BatchInput>&, const BatchSettings&)> bake;
};

/// The library call of a BatchCommand: \p bake (bake_batch, bake_robot_batch) with
/// \p options (BatchOptions, RobotBatchOptions) and the settings given at run time.
template <class Options>
auto bake_with(Options options,
               BatchResult (*bake)(const std::vector<BatchInput>&, const Options&)) {
  return [options, bake](const std::vector<BatchInput>& inputs, const BatchSettings& settings) {
    Options o = options;
    static_cast<BatchSettings&>(o) = settings;
    return bake(inputs, o);
  };
}

/// The batch of `bake`: meshes through bake_batch with \p request.
BatchCommand mesh_batch(const BakeRequest& request);

/// Registers --from-list, --jobs, --shard, --cache, --report, --ext and --relative-to.
void add_batch_flags(CLI::App& sub, BatchFlags& flags, const BatchCommand& command);

/// A batch is several inputs, a folder, a list, or any batch flag.
bool is_batch(const std::vector<std::string>& inputs, const BatchFlags& flags,
              const BatchCommand& command);

/// Bakes the inputs into the folder \p out; exit 0 when every input of the shard is
/// baked or cached, 2 when some failed on bad input only, 1 when some failed otherwise.
int run_batch(const std::vector<std::string>& inputs, const std::string& out,
              const BatchFlags& flags, const BatchCommand& command, bool quiet);

}  // namespace medspheres::cli
