// medspheres bake|robot IN... -o DIR: many meshes or robots, sharded, cached, with a report.
#include "cmd_batch.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli_common.h"
#include "medspheres/batch/batch.h"
#include "medspheres/io.h"
#include "medspheres/thread_option.h"

namespace medspheres::cli {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> all_paths(const std::vector<std::string>& inputs, const BatchFlags& f) {
  std::vector<std::string> paths = inputs;
  if (f.from_list.empty()) return paths;
  std::vector<std::string> listed;
  if (f.from_list == "-") {
    listed = read_path_list(std::cin, "standard input");
  } else {
    std::ifstream in(f.from_list);
    if (!in)
      throw InputError::option(ErrorKind::kFileUnreadable, "from_list", f.from_list,
                               "cannot open '" + f.from_list + "'");
    listed = read_path_list(in, f.from_list);
  }
  paths.insert(paths.end(), listed.begin(), listed.end());
  return paths;
}

// The report's format from its extension, checked before any work.
bool report_is_csv(const std::string& report) {
  const std::string ext = fs::path(report).extension().string();
  if (ext != ".json" && ext != ".csv")
    throw InputError::option(
        ErrorKind::kOutOfRange, "report", report,
        "must end in .json or .csv (the report's format), got '" + report + "'");
  check_output_path(report);
  return ext == ".csv";
}

std::string clock_text(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

// A robot's planner summary for its row ("" without one): the default configuration's
// origin, the checked pairs and the estimate's false self-collisions.
std::string planner_text(const std::optional<BatchPlannerSummary>& s) {
  if (!s) return "";
  std::string t =
      "default " + s->default_from + ", " + count_text(s->checked_pairs, "pair") + " checked, ";
  if (s->estimate_samples > 0)
    t += std::to_string(s->false_positives) + " false and " + std::to_string(s->false_negatives) +
         " missed self-collisions in " + std::to_string(s->estimate_samples) + " configurations, ";
  return t;
}

std::string row_line(const BatchRow& r) {
  if (r.outcome == BatchOutcome::kFailed)
    return "failed " + (r.input_error ? message_of(*r.input_error) : r.input.path + ": " + r.error);
  return std::string(to_string(r.outcome)) + " " + r.input.path + " -> " + r.output + " (" +
         (r.links > 0 ? count_text(r.links, "link") + ", " : std::string()) +
         count_text(r.spheres, "sphere") + ", " + planner_text(r.planner) +
         number_text(r.seconds, 3) + " s)";
}

// An input's warnings (the mesh loader's, cuRobo's URDF parser's), one line each.
void print_warnings(const BatchRow& row) {
  for (const std::string& w : row.warnings)
    std::cerr << "medspheres: warning: " << row.input.path << ": " << w << "\n";
}

// A bar with counts and time left on a terminal; one plain line per input otherwise.
BatchProgressFn progress_printer(bool quiet, std::shared_ptr<ProgressBar> bar) {
  if (quiet) return nullptr;
  const auto start = std::chrono::steady_clock::now();
  const bool terminal = stderr_is_terminal();
  return [=](const BatchRow& row, std::size_t done, std::size_t total) {
    const double spent =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!terminal) {
      std::cerr << "[" << done << "/" << total << "] " << row_line(row) << "\n";
      print_warnings(row);
      return;
    }
    if (row.outcome == BatchOutcome::kFailed || !row.warnings.empty()) {
      bar->finish();
      if (row.outcome == BatchOutcome::kFailed) std::cerr << row_line(row) << "\n";
      print_warnings(row);
    }
    const double left = spent / static_cast<double>(done) * static_cast<double>(total - done);
    bar->update(
        std::to_string(done) + "/" + std::to_string(total) + ", " + clock_text(left) + " left",
        done, total);
  };
}

void print_summary(const BatchResult& r, const std::string& out) {
  std::printf("%-10s %7s\n", "outcome", "inputs");
  for (BatchOutcome o : {BatchOutcome::kBaked, BatchOutcome::kCached, BatchOutcome::kFailed})
    std::printf("%-10s %7zu\n", to_string(o), r.count(o));
  if (r.other_shards > 0) std::printf("%-10s %7zu (other shards)\n", "elsewhere", r.other_shards);
  std::printf("%-10s %7zu %s s wall clock, outputs under %s\n", "total", r.rows.size(),
              number_text(r.seconds, 3).c_str(), out.c_str());
  for (const BatchRow& row : r.rows)
    if (row.outcome == BatchOutcome::kFailed) std::printf("  %s\n", row_line(row).c_str());
  std::fflush(stdout);
}

int exit_code(const BatchResult& r) {
  int code = kExitOk;
  for (const BatchRow& row : r.rows) {
    if (row.outcome != BatchOutcome::kFailed) continue;
    if (!row.input_error) return kExitFailure;
    code = kExitBadInput;
  }
  return code;
}

}  // namespace

BatchCommand mesh_batch(const BakeRequest& request) {
  return {"mesh",
          "Meshes baked at once, each on (cores / jobs) threads unless --threads is given "
          "(default 0: one per core)",
          "Extensions a folder is scanned for (default: stl,obj,ply,off,dae,gltf,glb,fbx,3ds)",
          {},
          true,
          bake_with(BatchOptions{{}, request}, bake_batch)};
}

void add_batch_flags(CLI::App& sub, BatchFlags& f, const BatchCommand& c) {
  sub.add_option("--from-list", f.from_list,
                 "Also bake the paths in this file, one a line ('-': standard input)")
      ->check(non_empty);
  sub.add_option("--jobs", f.jobs, c.jobs_help)->capture_default_str();
  sub.add_option("--shard", f.shard,
                 "i/N: bake only share i of N (by a hash of each input's relative path)")
      ->check(non_empty);
  sub.add_option("--cache", f.cache,
                 std::string("Cache folder: a ") + c.noun +
                     " already baked with the same options is copied from it")
      ->check(non_empty);
  sub.add_option("--report", f.report, "Write one row per input to this .json or .csv file")
      ->check(non_empty);
  sub.add_option("--ext", f.extensions, c.extensions_help)->delimiter(',');
  sub.add_option("--relative-to", f.relative_to,
                 "Files given by path mirror their path relative to this folder (default: the "
                 "working directory; outside it, their name)")
      ->check(non_empty);
}

bool is_batch(const std::vector<std::string>& inputs, const BatchFlags& f, const BatchCommand& c) {
  std::error_code ec;
  return inputs.size() != 1 || fs::is_directory(inputs.front(), ec) || !f.from_list.empty() ||
         (c.jobs_make_a_batch && f.jobs != 0) || !f.shard.empty() || !f.cache.empty() ||
         !f.report.empty() || !f.extensions.empty() || !f.relative_to.empty();
}

int run_batch(const std::vector<std::string>& inputs, const std::string& out,
              const BatchFlags& flags, const BatchCommand& command, bool quiet) {
  // Everything that needs no mesh first: flags, the output folder, the report's path.
  if (out.empty())
    throw InputError::option(ErrorKind::kConflict, "output", "",
                             "names the output folder and is required with several inputs, a "
                             "folder, --from-list or a batch option");
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    throw InputError::option(ErrorKind::kOutOfRange, "output", out,
                             "'" + out +
                                 "' exists and is not a folder (-o names the output "
                                 "folder of a batch)");
  check_threads_option(flags.jobs, "jobs");
  BatchSettings options;
  options.output_dir = out;
  options.cache_dir = flags.cache;
  options.jobs = flags.jobs;
  if (!flags.shard.empty()) options.shard = parse_shard(flags.shard);
  const bool csv = !flags.report.empty() && report_is_csv(flags.report);
  InputScan scan;
  scan.extensions = flags.extensions.empty() ? command.extensions : flags.extensions;
  scan.relative_to = flags.relative_to;
  std::vector<BatchInput> list;
  try {
    list = collect_inputs(all_paths(inputs, flags), scan);
  } catch (const InputError& e) {
    if (e.field() == "extensions") throw e.with_field("ext");  // the library's name of --ext
    throw;
  }
  if (list.empty())
    throw InputError(ErrorKind::kFileMissing, inputs.empty() ? flags.from_list : inputs.front(),
                     std::string("no ") + command.noun +
                         " to bake (a folder is scanned for the extensions of --ext)");

  auto bar = std::make_shared<ProgressBar>(!quiet);
  options.progress = progress_printer(quiet, bar);
  const BatchResult result = command.bake(list, options);
  bar->finish();
  if (!flags.report.empty())
    write_file_atomically(flags.report, csv ? batch_report_csv(result) : batch_report_json(result));
  if (!quiet) print_summary(result, out);
  if (quiet)  // quiet drops progress and the summary, not why an input failed
    for (const BatchRow& row : result.rows)
      if (row.outcome == BatchOutcome::kFailed)
        std::cerr << "medspheres: error: " << row_line(row) << "\n";
  return exit_code(result);
}

}  // namespace medspheres::cli
