// Baking many meshes: each through bake_mesh, in parallel, cached, one output per input.
#include "medspheres/bake/batch.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <thread>

#include <nlohmann/json.hpp>

#include "medspheres/bake/batch_cache.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/threads.h"

namespace medspheres {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// \p set with its source's mesh named \p name: a cached file baked from another path.
SphereSet renamed(SphereSet set, const std::string& name) {
  nlohmann::ordered_json meta = nlohmann::ordered_json::parse(set.metadata_json);
  if (meta.contains("source") && meta["source"].is_object()) meta["source"]["mesh"] = name;
  set.metadata_json = meta.dump();
  return set;
}

// The sphere count and the recorded nerr of a set as written.
void describe(const SphereSet& set, BatchRow& row) {
  row.spheres = set.size();
  const nlohmann::json meta = nlohmann::json::parse(set.metadata_json);
  const auto stats = meta.find("stats");
  if (stats != meta.end() && stats->contains("nerr") && (*stats)["nerr"].is_number())
    row.nerr = (*stats)["nerr"].get<double>();
}

void write_output(const std::string& path, const std::string& text) {
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);  // write reports what is wrong
  write_file_atomically(path, text);
}

struct Job {
  const BatchOptions& options;
  const BakeRequest& request;
  const BakeCache* cache;
};

// One input: from the cache, or loaded, baked, stored and written. Throws on failure.
void bake_input(const Job& job, BatchRow& row) {
  const BatchInput& in = row.input;
  const std::string sha = file_sha256(in.path);
  std::string key;
  if (job.cache) {
    key = bake_cache_key(sha, fs::path(in.path).extension().string(), job.request);
    if (std::optional<SphereSet> hit = job.cache->find(key)) {
      const SphereSet set = renamed(std::move(*hit), in.relative);
      write_output(row.output, sphere_set_to_json(set));
      describe(set, row);
      row.outcome = BatchOutcome::kCached;
      return;
    }
  }
  LoadedMesh loaded = load_mesh(in.path);
  row.warnings = std::move(loaded.warnings);
  const BakeOutcome baked = bake_mesh(loaded.mesh, loaded.report, job.request, in.relative, sha);
  const std::string text = sphere_set_to_json(baked.spheres);
  if (job.cache) job.cache->store(key, text);
  write_output(row.output, text);
  describe(baked.spheres, row);
  row.outcome = BatchOutcome::kBaked;
}

void run_input(const Job& job, BatchRow& row) {
  const Clock::time_point start = Clock::now();
  try {
    bake_input(job, row);
  } catch (const InputError& e) {
    row.input_error = e;
    row.error = e.what();
  } catch (const std::exception& e) {
    row.error = e.what();
  }
  if (!row.error.empty()) row.outcome = BatchOutcome::kFailed;
  row.seconds = seconds_since(start);
}

// The request every input is baked with: times left out, threads shared among the jobs.
BakeRequest batch_request(const BatchOptions& o, int jobs) {
  BakeRequest r = o.request;
  r.record_seconds = false;
  r.medial.progress = nullptr;
  if (r.medial.threads == 0) r.medial.threads = std::max(1, thread_count(0) / jobs);
  return r;
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

BatchResult bake_batch(const std::vector<BatchInput>& inputs, const BatchOptions& options) {
  const Clock::time_point start = Clock::now();
  check_threads(options.jobs);
  validate(options.request);
  BatchResult result;
  for (const BatchInput& in : inputs) {
    if (!in_shard(in.relative, options.shard)) {
      ++result.other_shards;
      continue;
    }
    BatchRow row;
    row.input = in;
    row.output = (fs::path(options.output_dir) / output_relative(in.relative)).string();
    result.rows.push_back(std::move(row));
  }
  std::error_code ec;
  fs::create_directories(options.output_dir, ec);
  if (!fs::is_directory(options.output_dir))
    throw InputError::option(ErrorKind::kWriteFailed, "output", options.output_dir,
                             "'" + options.output_dir + "' is not a folder and cannot be made one");
  std::optional<BakeCache> cache;
  if (!options.cache_dir.empty()) cache.emplace(options.cache_dir);

  int jobs = std::max(1, std::min(thread_count(options.jobs),
                                  static_cast<int>(std::max<std::size_t>(1, result.rows.size()))));
  const BakeRequest request = batch_request(options, thread_count(options.jobs));
  const Job job{options, request, cache ? &*cache : nullptr};
  std::atomic<std::size_t> next{0};
  std::mutex report;
  std::size_t done = 0;
  auto worker = [&] {
    for (std::size_t i = next++; i < result.rows.size(); i = next++) {
      run_input(job, result.rows[i]);
      std::lock_guard<std::mutex> lock(report);
      ++done;
      if (options.progress) options.progress(result.rows[i], done, result.rows.size());
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < jobs; ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace medspheres
