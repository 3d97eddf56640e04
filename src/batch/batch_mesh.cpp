// Baking many meshes: each through bake_mesh, on the batch driver, one file per input.
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "batch_driver.h"
#include "medspheres/batch/batch.h"
#include "medspheres/batch/batch_cache.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/sha256.h"

namespace medspheres {

namespace fs = std::filesystem;

namespace {

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

// One input: from the cache, or loaded, baked, stored and written. Throws on failure.
void bake_input(const BakeRequest& request, const BakeCache* cache, BatchRow& row) {
  const BatchInput& in = row.input;
  const std::string sha = file_sha256(in.path);
  std::string key;
  if (cache) {
    key = bake_cache_key(sha, fs::path(in.path).extension().string(), request);
    if (std::optional<SphereSet> hit = cache->find(key)) {
      const SphereSet set = renamed(std::move(*hit), in.relative);
      write_file_atomically(row.output, sphere_set_to_json(set));
      describe(set, row);
      row.outcome = BatchOutcome::kCached;
      return;
    }
  }
  LoadedMesh loaded = load_mesh(in.path);
  row.warnings = std::move(loaded.warnings);
  const BakeOutcome baked = bake_mesh(loaded.mesh, loaded.report, request, in.relative, sha);
  const std::string text = sphere_set_to_json(baked.spheres);
  if (cache) cache->store(key, text);
  write_file_atomically(row.output, text);
  describe(baked.spheres, row);
  row.outcome = BatchOutcome::kBaked;
}

}  // namespace

BatchResult bake_batch(const std::vector<BatchInput>& inputs, const BatchOptions& options) {
  const BakeRequest request = batch_request(options.request, options.jobs);
  auto run = [&request](BatchRow& row, const BakeCache* cache) { bake_input(request, cache, row); };
  return run_batch(inputs, options, {BatchItems::kMeshes, output_relative, run});
}

}  // namespace medspheres
