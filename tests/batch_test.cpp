// Batch baking: inputs, shards, the cache and the runner, against their definitions and
// against single bakes of the same meshes.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/batch/batch.h"
#include "medspheres/batch/batch_cache.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/sha256.h"
#include "support/file_tree.h"
#include "support/mesh_library.h"
#include "support/mesh_writers.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::test;
namespace fs = std::filesystem;

namespace {

BakeRequest small_request() {
  BakeRequest r;
  r.medial.resolution = 10;
  return r;
}

std::vector<std::string> paths_of(const std::vector<BatchInput>& inputs) {
  std::vector<std::string> out;
  for (const BatchInput& in : inputs) out.push_back(in.relative);
  return out;
}

}  // namespace

TEST_CASE("parse_shard: i/N with 0 <= i < N, anything else named", "[batch]") {
  CHECK(parse_shard("0/1").count == 1);
  CHECK(parse_shard("3/4").index == 3);
  for (const std::string bad :
       {"", "1", "4/4", "-1/4", "1/0", "a/2", "1/2/3", " 1/2", "1/+2", "0/4294967296"}) {
    INFO(bad);
    try {
      parse_shard(bad);
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(e.field() == "shard");
      CHECK(e.kind() == ErrorKind::kOutOfRange);
    }
  }
}

TEST_CASE("shards: each path in exactly one, balanced, few moves from N to N+1", "[batch]") {
  std::vector<std::string> paths;
  for (int i = 0; i < 4000; ++i)
    paths.push_back("dir" + std::to_string(i % 7) + "/m" + std::to_string(i) + ".stl");
  for (std::uint64_t n : {1, 2, 3, 8}) {
    std::vector<std::size_t> sizes(n, 0);
    for (const std::string& p : paths) {
      std::size_t holders = 0;
      for (std::uint64_t i = 0; i < n; ++i) holders += in_shard(p, {i, n}) ? 1 : 0;
      REQUIRE(holders == 1);
      ++sizes[shard_of(p, n)];
    }
    // Binomial(4000, 1/n): every share within 5 standard deviations of its mean.
    const double mean = 4000.0 / n, sd = std::sqrt(4000.0 * (1.0 / n) * (1.0 - 1.0 / n));
    for (std::size_t s : sizes) CHECK(std::abs(s - mean) <= 5 * sd + 1e-9);
  }
  // From 4 to 5 shards a path moves only to the new shard, about 1/5 of them.
  std::size_t moved = 0;
  for (const std::string& p : paths) {
    const auto before = shard_of(p, 4), after = shard_of(p, 5);
    if (before != after) {
      CHECK(after == 4);
      ++moved;
    }
  }
  const double sd = std::sqrt(4000.0 * 0.2 * 0.8);
  CHECK(std::abs(static_cast<double>(moved) - 800.0) <= 5 * sd);
}

TEST_CASE("collect_inputs: folders by extension, files by path, one output each", "[batch]") {
  TempDir dir;
  for (const std::string f : {"a/x.STL", "a/b/y.obj", "a/b/notes.txt", "a/c.off", "z.ply"}) {
    fs::create_directories((dir.path() / f).parent_path());
    dir.write(f, "solid");
  }
  const std::vector<BatchInput> in = collect_inputs({dir.file("a")});
  CHECK(paths_of(in) == std::vector<std::string>{"b/y.obj", "c.off", "x.STL"});
  CHECK(paths_of(collect_inputs({dir.file("a")}, {{"obj"}, ""})) ==
        std::vector<std::string>{"b/y.obj"});
  // Files relative to relative_to; outside it, by name; the same file twice kept once.
  InputScan scan;
  scan.relative_to = dir.file("a");
  const std::vector<BatchInput> files =
      collect_inputs({dir.file("a/b/y.obj"), dir.file("z.ply"), dir.file("a/b/../b/y.obj")}, scan);
  CHECK(paths_of(files) == std::vector<std::string>{"b/y.obj", "z.ply"});
  // Two files with one output.
  dir.write("a/x.obj", "");
  CHECK_THROWS_AS(collect_inputs({dir.file("a")}), InputError);
  CHECK_THROWS_AS(collect_inputs({dir.file("a")}, {{"st/l"}, ""}), InputError);
  CHECK(output_relative("a/b/arm.stl") == "a/b/arm.spheres.json");
  CHECK(output_relative("arm.tar.obj") == "arm.tar.spheres.json");
}

TEST_CASE("read_path_list: one path a line, blanks and comments skipped", "[batch]") {
  std::istringstream in("a.stl\r\n\n  # a comment\n  b c.obj  \n#x\nd/e.off");
  CHECK(read_path_list(in, "list") == std::vector<std::string>{"a.stl", "b c.obj", "d/e.off"});
}

TEST_CASE("bake_cache_key: every result-changing option, not threads", "[batch]") {
  const std::string sha(64, 'a');
  const BakeRequest base = small_request();
  const std::string key = bake_cache_key(sha, ".OFF", base);
  CHECK(key.size() == 64);
  CHECK(bake_cache_key(sha, "off", base) == key);
  BakeRequest threads = base;
  threads.medial.threads = 7;
  CHECK(bake_cache_key(sha, ".off", threads) == key);
  std::vector<BakeRequest> changed(13, base);
  changed[0].medial.resolution = 11;
  changed[1].medial.object_angle = 0.61;
  changed[2].max_spheres = 5;
  changed[3].target_error = 0.1;
  changed[4].dilate = true;
  changed[5].cover = Length{0.01, true};
  changed[6].seed = 2;
  changed[7].measure = false;
  changed[8].method = BakeMethod::kCover;
  changed[9].medial.medial_tolerance = 1e-4;
  changed[10].solid = SolidKind::kRobust;
  changed[11].robust.resolution = 64;
  changed[12].robust_thickness = Length{0.01, true};
  std::set<std::string> keys = {key, bake_cache_key(std::string(64, 'b'), ".off", base),
                                bake_cache_key(sha, ".stl", base)};
  for (const BakeRequest& r : changed) keys.insert(bake_cache_key(sha, ".off", r));
  CHECK(keys.size() == 16);
}

TEST_CASE("bake_batch: each row as a single bake, a bad mesh is a row and not a stop", "[batch]") {
  TempDir dir;
  for (const std::string sub : {"in/sub"}) fs::create_directories(dir.path() / sub);
  dir.write("in/box.off", to_off(make_box({1, 0.5, 0.25}, 2)));
  dir.write("in/sub/ball.stl", to_stl_binary(make_icosphere(1.0, 2)));
  dir.write("in/sub/broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  dir.write("in/flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  BatchOptions o;
  o.request = small_request();
  o.output_dir = dir.file("out");
  o.jobs = 2;
  std::size_t calls = 0;
  o.progress = [&](const BatchRow&, std::size_t done, std::size_t total) {
    ++calls;
    CHECK(done == calls);
    CHECK(total == 4);
  };
  const BatchResult r = bake_batch(collect_inputs({dir.file("in")}), o);
  REQUIRE(r.rows.size() == 4);
  CHECK(calls == 4);
  CHECK(r.count(BatchOutcome::kBaked) == 2);
  CHECK(r.count(BatchOutcome::kFailed) == 2);
  for (const BatchRow& row : r.rows) {
    INFO(row.input.relative);
    if (row.outcome == BatchOutcome::kFailed) {
      REQUIRE(row.input_error);
      CHECK_FALSE(fs::exists(row.output));
      continue;
    }
    // The oracle: the pipeline on the same mesh and name, without times.
    BakeRequest single = o.request;
    single.record_seconds = false;
    const LoadedMesh loaded = load_mesh(row.input.path);
    const BakeOutcome b = bake_mesh(loaded.mesh, loaded.report, single, row.input.relative,
                                    file_sha256(row.input.path));
    CHECK(read_file(row.output) == sphere_set_to_json(b.spheres));
    CHECK(row.spheres == b.spheres.size());
    CHECK(row.output == (fs::path(o.output_dir) / output_relative(row.input.relative)).string());
    CHECK(read_file(row.output).find("seconds") == std::string::npos);
  }
  const nlohmann::json report = nlohmann::json::parse(batch_report_json(r));
  CHECK(report["rows"].size() == 4);
  CHECK(report["totals"]["failed"] == 2);
  const std::string csv = batch_report_csv(r);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 5);
}

TEST_CASE("shards run one after another give the unsharded run's files, bit for bit", "[batch]") {
  TempDir dir;
  write_mesh_library(dir.file("lib"), 12, 7, 100, 1500);
  const std::vector<BatchInput> inputs = collect_inputs({dir.file("lib")});
  REQUIRE(inputs.size() == 12);
  BatchOptions whole;
  whole.request = small_request();
  whole.output_dir = dir.file("whole");
  const BatchResult all = bake_batch(inputs, whole);
  for (const BatchRow& row : all.rows)
    if (!row.error.empty()) UNSCOPED_INFO(row.error);
  CHECK(all.count(BatchOutcome::kBaked) == 12);
  const auto expected = file_tree(dir.file("whole"));
  REQUIRE(expected.size() == 12);

  for (const bool cached : {false, true}) {
    const std::string out = dir.file(cached ? "sharded_cached" : "sharded");
    std::size_t rows = 0;
    for (std::uint64_t i = 0; i < 3; ++i) {
      BatchOptions o = whole;
      o.output_dir = out;
      o.shard = {i, 3};
      o.jobs = 1 + static_cast<int>(i % 2);
      if (cached) o.cache_dir = dir.file("cache");
      const BatchResult part = bake_batch(inputs, o);
      rows += part.rows.size();
      CHECK(part.rows.size() + part.other_shards == 12);
    }
    CHECK(rows == 12);
    CHECK(file_tree(out) == expected);
  }
  // A rerun with the warm cache copies every file, to the same bytes.
  BatchOptions again = whole;
  again.output_dir = dir.file("again");
  again.cache_dir = dir.file("cache");
  const BatchResult hit = bake_batch(inputs, again);
  CHECK(hit.count(BatchOutcome::kCached) == 12);
  CHECK(file_tree(dir.file("again")) == expected);
}

TEST_CASE("cache: a rerun after a kill bakes only what is missing, torn entries are rebaked",
          "[batch]") {
  TempDir dir;
  write_mesh_library(dir.file("lib"), 6, 3, 100, 800);
  const std::vector<BatchInput> inputs = collect_inputs({dir.file("lib")});
  BatchOptions o;
  o.request = small_request();
  o.output_dir = dir.file("out");
  o.cache_dir = dir.file("cache");
  o.shard = {0, 2};  // what a killed run had finished
  const BatchResult first = bake_batch(inputs, o);
  std::set<std::string> finished;
  for (const BatchRow& row : first.rows) finished.insert(row.input.relative);
  o.shard = {};
  const BatchResult second = bake_batch(inputs, o);
  REQUIRE(second.rows.size() == 6);
  for (const BatchRow& row : second.rows) {
    INFO(row.input.relative);
    CHECK(row.outcome ==
          (finished.count(row.input.relative) ? BatchOutcome::kCached : BatchOutcome::kBaked));
  }
  // A torn entry (only a hand or another tool can leave one) is a miss, baked and stored.
  BakeRequest keyed = o.request;
  keyed.record_seconds = false;
  const BatchInput& torn = inputs.front();
  const std::string key =
      bake_cache_key(file_sha256(torn.path), fs::path(torn.path).extension().string(), keyed);
  const BakeCache cache(o.cache_dir);
  REQUIRE(cache.find(key).has_value());
  write_file_atomically(cache.path_of(key), "{\"spheres\": [[0, 0");
  CHECK_FALSE(cache.find(key).has_value());
  const auto before = file_tree(dir.file("out"));
  const BatchResult third = bake_batch(inputs, o);
  for (const BatchRow& row : third.rows)
    CHECK(row.outcome ==
          (row.input.relative == torn.relative ? BatchOutcome::kBaked : BatchOutcome::kCached));
  CHECK(cache.find(key).has_value());
  CHECK(file_tree(dir.file("out")) == before);
}

TEST_CASE("cache: the same bytes under another name give that name's own file", "[batch]") {
  TempDir dir;
  const std::string mesh = to_off(make_torus(1.0, 0.3, 12, 6));
  fs::create_directories(dir.path() / "a");
  fs::create_directories(dir.path() / "b");
  dir.write("a/one.off", mesh);
  dir.write("b/two.off", mesh);
  BatchOptions o;
  o.request = small_request();
  o.output_dir = dir.file("out");
  o.cache_dir = dir.file("cache");
  o.jobs = 1;
  const BatchResult r = bake_batch(collect_inputs({dir.file("a"), dir.file("b")}), o);
  REQUIRE(r.rows.size() == 2);
  CHECK(r.rows[0].outcome == BatchOutcome::kBaked);
  CHECK(r.rows[1].outcome == BatchOutcome::kCached);
  // The oracle: an uncached bake of two.off.
  BatchOptions fresh = o;
  fresh.cache_dir.clear();
  fresh.output_dir = dir.file("fresh");
  bake_batch(collect_inputs({dir.file("b")}), fresh);
  CHECK(read_file(dir.file("out/two.spheres.json")) ==
        read_file(dir.file("fresh/two.spheres.json")));
  CHECK(read_file(dir.file("out/two.spheres.json")).find("\"two.off\"") != std::string::npos);
}

TEST_CASE("write_mesh_library: every mesh within the triangle range", "[batch]") {
  TempDir dir;
  const auto library = write_mesh_library(dir.file("lib"), 40, 11, 100, 20000);
  REQUIRE(library.size() == 40);
  for (const LibraryMesh& m : library) {
    INFO(m.relative);
    CHECK(m.triangles >= 100);
    CHECK(m.triangles <= 20000);
    CHECK(load_mesh(dir.file("lib/" + m.relative)).mesh.triangles.size() == m.triangles);
  }
}
