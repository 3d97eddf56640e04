// The batch driver: the shard's rows run on a pool of jobs, cached, one output per input.
#include "medspheres/batch/batch.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "batch_driver.h"
#include "medspheres/batch/batch_cache.h"
#include "medspheres/threads.h"

namespace medspheres {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The folders from \p dir up that do not exist yet, deepest first.
std::vector<fs::path> missing_folders(fs::path dir) {
  std::vector<fs::path> missing;
  std::error_code ec;
  for (; !dir.empty() && !fs::exists(dir, ec); dir = dir.parent_path()) missing.push_back(dir);
  return missing;
}

// Runs one input; \p made gets the folders made for its output (deepest first).
void run_input(const BatchWork& work, const BakeCache* cache, BatchRow& row,
               std::vector<fs::path>& made) {
  const Clock::time_point start = Clock::now();
  try {
    std::error_code ec;  // the work reports what is wrong with the folder
    const fs::path folder = fs::path(row.output).parent_path();
    made = missing_folders(folder);
    fs::create_directories(folder, ec);
    work.run(row, cache);
  } catch (const InputError& e) {
    row.input_error = e;
    row.error = e.what();
  } catch (const std::exception& e) {
    row.error = e.what();
  }
  if (!row.error.empty()) row.outcome = BatchOutcome::kFailed;
  row.seconds = seconds_since(start);
}

// No output may be a folder that holds another: replacing it would remove the other.
void check_nesting(const std::vector<BatchInput>& inputs, const BatchWork& work) {
  std::map<std::string, const BatchInput*> by_output;
  for (const BatchInput& in : inputs) by_output.emplace(work.output_relative(in.relative), &in);
  for (const auto& [out, in] : by_output) {
    const auto inner = by_output.lower_bound(out + "/");
    if (inner != by_output.end() && inner->first.compare(0, out.size() + 1, out + "/") == 0)
      throw InputError(ErrorKind::kConflict, in->path,
                       "its output " + out + " would hold the output " + inner->first + " of " +
                           inner->second->path);
  }
}

}  // namespace

const char* to_string(BatchOutcome outcome) {
  switch (outcome) {
    case BatchOutcome::kBaked:
      return "baked";
    case BatchOutcome::kCached:
      return "cached";
    case BatchOutcome::kFailed:
      break;
  }
  return "failed";
}

std::size_t BatchResult::count(BatchOutcome outcome) const {
  return static_cast<std::size_t>(std::count_if(
      rows.begin(), rows.end(), [outcome](const BatchRow& r) { return r.outcome == outcome; }));
}

int batch_threads_each(int jobs) {
  check_threads(jobs);
  return std::max(1, thread_count(0) / thread_count(jobs));
}

BakeRequest batch_request(BakeRequest request, int jobs) {
  request.record_seconds = false;
  request.medial.progress = nullptr;
  if (request.medial.threads == 0) request.medial.threads = batch_threads_each(jobs);
  validate(request);
  return request;
}

BatchResult run_batch(const std::vector<BatchInput>& inputs, const BatchSettings& options,
                      const BatchWork& work) {
  const Clock::time_point start = Clock::now();
  check_threads(options.jobs);
  check_nesting(inputs, work);
  BatchResult result;
  result.items = work.items;
  for (const BatchInput& in : inputs) {
    if (!in_shard(in.relative, options.shard)) {
      ++result.other_shards;
      continue;
    }
    BatchRow row;
    row.input = in;
    row.output = (fs::path(options.output_dir) / work.output_relative(in.relative)).string();
    result.rows.push_back(std::move(row));
  }
  std::optional<BakeCache> cache;  // a cache folder that is a file fails before any output
  if (!options.cache_dir.empty()) cache.emplace(options.cache_dir);
  std::error_code ec;
  fs::create_directories(options.output_dir, ec);
  if (!fs::is_directory(options.output_dir))
    throw InputError::option(ErrorKind::kWriteFailed, "output", options.output_dir,
                             "'" + options.output_dir + "' is not a folder and cannot be made one");

  const int jobs =
      std::max(1, std::min(thread_count(options.jobs),
                           static_cast<int>(std::max<std::size_t>(1, result.rows.size()))));
  const BakeCache* const store = cache ? &*cache : nullptr;
  std::atomic<std::size_t> next{0};
  std::mutex report;
  std::size_t done = 0;
  std::vector<std::vector<fs::path>> made(result.rows.size());
  auto worker = [&] {
    for (std::size_t i = next++; i < result.rows.size(); i = next++) {
      run_input(work, store, result.rows[i], made[i]);
      std::lock_guard<std::mutex> lock(report);
      ++done;
      if (options.progress) options.progress(result.rows[i], done, result.rows.size());
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < jobs; ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  // A failed input leaves no folder of its own: those made for it are removed when empty
  // (after every worker, so that none is removed under another's output).
  for (std::size_t i = 0; i < result.rows.size(); ++i)
    if (result.rows[i].outcome == BatchOutcome::kFailed)
      for (const fs::path& folder : made[i]) fs::remove(folder, ec);
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace medspheres
