// Baking many robots on the batch driver: each row's folder against a single robot bake of
// the same URDF, shards against the unsharded run, the cache, a broken URDF as a row.
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/batch/batch_robot.h"
#include "medspheres/error.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/sha256.h"
#include "support/coarse_arm.h"
#include "support/file_tree.h"
#include "support/mesh_writers.h"
#include "support/sanitizer_build.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::test;
namespace fs = std::filesystem;

namespace {

std::string urdf_link(const std::string& name, const std::string& geometry,
                      const std::string& origin = "") {
  return "  <link name=\"" + name + "\"><collision>" + origin + "<geometry>" + geometry +
         "</geometry></collision></link>\n";
}

std::string joint(const std::string& name, const std::string& parent, const std::string& child) {
  return "  <joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent +
         "\"/><child link=\"" + child +
         "\"/><origin xyz=\"0 0 0.1\"/><axis xyz=\"0 0 1\"/>"
         "<limit lower=\"-1\" upper=\"1\" velocity=\"1\" effort=\"1\"/></joint>\n";
}

std::string robot(const std::string& name, const std::string& body) {
  return "<?xml version=\"1.0\"?>\n<robot name=\"" + name + "\">\n" + body + "</robot>\n";
}

// Four robots of primitives and small meshes in nested folders, and one broken URDF:
// lib/arm/arm.urdf, lib/gripper.urdf, lib/sub/pole.urdf, lib/sub/ring.urdf,
// lib/sub/broken.urdf (a mesh that does not exist).
void write_robots(const TempDir& dir) {
  fs::create_directories(dir.path() / "lib/arm/meshes");
  fs::create_directories(dir.path() / "lib/meshes");
  fs::create_directories(dir.path() / "lib/sub");
  dir.write("lib/arm/meshes/ball.obj", to_obj(make_icosphere(0.05, 1)));
  dir.write("lib/meshes/palm.stl", to_stl_binary(make_box({0.04, 0.03, 0.01}, 2)));
  dir.write("lib/meshes/ring.off", to_off(make_torus(0.05, 0.015, 12, 6)));
  dir.write("lib/arm/arm.urdf",
            robot("arm", urdf_link("base", "<box size=\"0.2 0.1 0.05\"/>") +
                             urdf_link("upper", "<mesh filename=\"meshes/ball.obj\"/>",
                                       "<origin xyz=\"0 0 0.05\" rpy=\"0.3 0 0\"/>") +
                             urdf_link("lower", "<cylinder radius=\"0.02\" length=\"0.1\"/>") +
                             joint("j1", "base", "upper") + joint("j2", "upper", "lower")));
  dir.write("lib/gripper.urdf",
            robot("gripper", urdf_link("palm", "<mesh filename=\"meshes/palm.stl\"/>") +
                                 urdf_link("finger", "<sphere radius=\"0.01\"/>") +
                                 joint("j", "palm", "finger")));
  dir.write("lib/sub/pole.urdf", robot("pole", urdf_link("pole", "<box size=\"0.02 0.02 0.3\"/>")));
  dir.write(
      "lib/sub/ring.urdf",
      robot("ring", urdf_link("ring", "<mesh filename=\"../meshes/ring.off\" scale=\"2 2 1\"/>") +
                        urdf_link("tip", "<cylinder radius=\"0.01\" length=\"0.05\"/>") +
                        joint("j", "ring", "tip")));
  dir.write("lib/sub/broken.urdf",
            robot("broken", urdf_link("base", "<mesh filename=\"missing.stl\"/>")));
}

RobotBatchOptions small_options(const std::string& out) {
  RobotBatchOptions o;
  o.output_dir = out;
  o.robot.bake.request.medial.resolution = 12;
  // 3 spheres a link in the sanitizer builds, and no covering sets there: the covers' bakes
  // took most of these tests' time (test_cover and test_robot_bake run them under the
  // sanitizers); every comparison holds at any budget and for either set.
  o.robot.bake.budget.per_link = test::kSanitizerBuild ? 3 : 6;
  o.robot.bake.outer = !test::kSanitizerBuild;
  // The self-collision matrix on 300 samples, not 10^4: these tests compare files, not
  // classes, and the matrix's sampling took most of their time.
  o.robot.planner.self_collision.samples = 300;
  return o;
}

// \p row's planner summary against the single bake \p b of its URDF, and its checked pairs
// against the SRDF the row wrote: every pair of the robot's \p n links with spheres that the
// SRDF does not disable.
void check_planner_summary(const BatchRow& row, const RobotFileResult& b, std::size_t n) {
  REQUIRE(row.planner);
  REQUIRE(b.bake.model.planner);
  CHECK(row.planner->default_from == b.bake.model.planner->default_from);
  CHECK(row.planner->estimate_samples == b.planner.estimate.samples);
  CHECK(row.planner->false_positives == b.planner.estimate.false_positives);
  CHECK(row.planner->false_negatives == b.planner.estimate.false_negatives);
  std::string srdf;
  for (const auto& [name, text] : file_tree(row.output))
    if (name.size() > 5 && name.compare(name.size() - 5, 5, ".srdf") == 0) srdf = text;
  REQUIRE_FALSE(srdf.empty());
  std::size_t disabled = 0;
  for (auto at = srdf.find("<disable_collisions"); at != std::string::npos;
       at = srdf.find("<disable_collisions", at + 1))
    ++disabled;
  CHECK(row.planner->checked_pairs == n * (n - 1) / 2 - disabled);
}

const std::set<std::string> kGood = {"arm/arm.urdf", "gripper.urdf", "sub/pole.urdf",
                                     "sub/ring.urdf"};

}  // namespace

TEST_CASE("bake_robot_batch: each folder as a single robot bake, a broken URDF is a row",
          "[batch][robot]") {
  TempDir dir;
  write_robots(dir);
  RobotBatchOptions o = small_options(dir.file("out"));
  o.jobs = 2;
  std::size_t calls = 0;
  o.progress = [&](const BatchRow&, std::size_t done, std::size_t total) {
    CHECK(done == ++calls);
    CHECK(total == 5);
  };
  const BatchResult r = bake_robot_batch(collect_inputs({dir.file("lib")}, {{"urdf"}, ""}), o);
  REQUIRE(r.rows.size() == 5);
  CHECK(r.items == BatchItems::kRobots);
  CHECK(r.count(BatchOutcome::kBaked) == 4);
  CHECK(r.count(BatchOutcome::kFailed) == 1);
  for (const BatchRow& row : r.rows) {
    INFO(row.input.relative << ": " << row.error);
    CHECK(row.output ==
          (fs::path(o.output_dir) / robot_output_relative(row.input.relative)).string());
    if (!kGood.count(row.input.relative)) {
      CHECK(row.outcome == BatchOutcome::kFailed);
      REQUIRE(row.input_error);
      CHECK(row.error.find("broken.urdf") != std::string::npos);
      CHECK(row.error.find("link 'base'") != std::string::npos);
      CHECK(row.error.find("missing.stl") != std::string::npos);
      CHECK_FALSE(fs::exists(row.output));
      continue;
    }
    REQUIRE(row.outcome == BatchOutcome::kBaked);
    // The oracle: the single-robot bake of the same URDF with the same job, without times.
    RobotJob single = o.robot;
    single.bake.request.record_seconds = false;
    const std::string alone = dir.file("alone/" + robot_output_relative(row.input.relative));
    fs::create_directories(fs::path(alone).parent_path());
    const RobotFileResult b = bake_robot_file(row.input.path, alone, single);
    CHECK(file_tree(row.output) == file_tree(alone));
    CHECK(row.links == b.bake.links.size());
    CHECK(row.spheres == b.spheres);
    CHECK(row.spheres > 0);
    check_planner_summary(row, b, row.links);  // every link of these robots has spheres
    CHECK(row.planner->default_from == "zero");
    // No times in the files: they are a pure function of the inputs.
    for (const auto& [name, text] : file_tree(row.output))
      CHECK(text.find("seconds") == std::string::npos);
  }
  const nlohmann::json report = nlohmann::json::parse(batch_report_json(r));
  CHECK(report["rows"][0].contains("links"));
  CHECK_FALSE(report["rows"][0].contains("nerr"));
  CHECK(report["totals"]["failed"] == 1);
  for (const auto& row : report["rows"])
    CHECK(row["checked_pairs"].is_null() == (row["outcome"] == "failed"));
  const std::string csv = batch_report_csv(r);
  CHECK(csv.rfind("input,relative,output,outcome,links,spheres,default_from,checked_pairs,"
                  "estimate_samples,false_positives,false_negatives,seconds,error\r\n",
                  0) == 0);
}

TEST_CASE(
    "robot shards one after another give the unsharded folders bit for bit, as do the "
    "cache and a resumed run",
    "[batch][robot]") {
  TempDir dir;
  write_robots(dir);
  const std::vector<BatchInput> inputs = collect_inputs({dir.file("lib")}, {{"urdf"}, ""});
  REQUIRE(inputs.size() == 5);
  const BatchResult all = bake_robot_batch(inputs, small_options(dir.file("whole")));
  CHECK(all.count(BatchOutcome::kBaked) == 4);
  const auto expected = file_tree(dir.file("whole"));
  REQUIRE(expected.size() >= 4 * 7);

  for (const bool cached : {false, true}) {
    const std::string out = dir.file(cached ? "sharded_cached" : "sharded");
    std::size_t rows = 0;
    for (std::uint64_t i = 0; i < 3; ++i) {
      RobotBatchOptions o = small_options(out);
      o.shard = {i, 3};
      o.jobs = 1 + static_cast<int>(i % 2);
      if (cached) o.cache_dir = dir.file("cache");
      const BatchResult part = bake_robot_batch(inputs, o);
      rows += part.rows.size();
      CHECK(part.rows.size() + part.other_shards == 5);
    }
    CHECK(rows == 5);
    CHECK(file_tree(out) == expected);
  }
  // A warm cache copies every good robot, to the same bytes; the broken one fails again.
  RobotBatchOptions again = small_options(dir.file("again"));
  again.cache_dir = dir.file("cache");
  const BatchResult hit = bake_robot_batch(inputs, again);
  CHECK(hit.count(BatchOutcome::kCached) == 4);
  CHECK(hit.count(BatchOutcome::kFailed) == 1);
  CHECK(file_tree(dir.file("again")) == expected);
  for (std::size_t i = 0; i < hit.rows.size(); ++i) {
    CHECK(hit.rows[i].links == all.rows[i].links);
    CHECK(hit.rows[i].spheres == all.rows[i].spheres);
    // The planner summary travels with the cache entry.
    REQUIRE(hit.rows[i].planner.has_value() == all.rows[i].planner.has_value());
    if (!hit.rows[i].planner) continue;
    CHECK(hit.rows[i].planner->default_from == all.rows[i].planner->default_from);
    CHECK(hit.rows[i].planner->checked_pairs == all.rows[i].planner->checked_pairs);
    CHECK(hit.rows[i].planner->estimate_samples == all.rows[i].planner->estimate_samples);
    CHECK(hit.rows[i].planner->false_positives == all.rows[i].planner->false_positives);
    CHECK(hit.rows[i].planner->false_negatives == all.rows[i].planner->false_negatives);
  }

  // A run killed after shard 0 of 2, resumed: what it finished is copied, the rest baked.
  RobotBatchOptions o = small_options(dir.file("resumed"));
  o.cache_dir = dir.file("cache2");
  o.shard = {0, 2};
  std::set<std::string> finished;
  for (const BatchRow& row : bake_robot_batch(inputs, o).rows)
    if (row.outcome == BatchOutcome::kBaked) finished.insert(row.input.relative);
  o.shard = {};
  for (const BatchRow& row : bake_robot_batch(inputs, o).rows) {
    INFO(row.input.relative);
    if (!kGood.count(row.input.relative)) continue;
    CHECK(row.outcome ==
          (finished.count(row.input.relative) ? BatchOutcome::kCached : BatchOutcome::kBaked));
  }
  CHECK(file_tree(dir.file("resumed")) == expected);

  // Another option is another key: nothing is copied.
  RobotBatchOptions other = small_options(dir.file("other"));
  other.cache_dir = dir.file("cache");
  other.robot.bake.budget.per_link = 5;
  CHECK(bake_robot_batch(inputs, other).count(BatchOutcome::kCached) == 0);
}

TEST_CASE("robot batch: a copy of the library elsewhere is found in the cache", "[batch][robot]") {
  TempDir dir;
  write_robots(dir);
  RobotBatchOptions o = small_options(dir.file("out"));
  o.cache_dir = dir.file("cache");
  const BatchResult first = bake_robot_batch(collect_inputs({dir.file("lib")}, {{"urdf"}, ""}), o);
  REQUIRE(first.count(BatchOutcome::kBaked) == 4);
  // The library copied to another folder (another depth too), baked with the same cache.
  fs::create_directories(dir.path() / "elsewhere/deeper");
  fs::copy(dir.path() / "lib", dir.path() / "elsewhere/deeper/lib", fs::copy_options::recursive);
  const std::vector<BatchInput> copied =
      collect_inputs({dir.file("elsewhere/deeper/lib")}, {{"urdf"}, ""});
  RobotBatchOptions from_copy = small_options(dir.file("out_copy"));
  from_copy.cache_dir = dir.file("cache");
  const BatchResult hit = bake_robot_batch(copied, from_copy);
  CHECK(hit.count(BatchOutcome::kCached) == 4);
  CHECK(hit.count(BatchOutcome::kFailed) == 1);
  // The oracle: the copy baked without a cache. The files are the same bytes.
  const BatchResult fresh = bake_robot_batch(copied, small_options(dir.file("out_fresh")));
  CHECK(fresh.count(BatchOutcome::kBaked) == 4);
  const auto cached_files = file_tree(dir.file("out_copy"));
  CHECK(cached_files == file_tree(dir.file("out_fresh")));
  // They differ from the first run's only where the robot file and the cuRobo
  // configurations (urdf_path) name what was read.
  const auto original = file_tree(dir.file("out"));
  REQUIRE(cached_files.size() == original.size());
  for (const auto& [name, text] : original) {
    INFO(name);
    REQUIRE(cached_files.count(name));
    const bool robot_file = name.find(".robot.json") != std::string::npos;
    if (!robot_file && name.find(".curobo") == std::string::npos) {
      CHECK(cached_files.at(name) == text);
      continue;
    }
    if (robot_file) {
      const auto meta = nlohmann::json::parse(cached_files.at(name))["metadata"];
      CHECK(meta["urdf"].get<std::string>().find("elsewhere/deeper/lib") != std::string::npos);
    }
    std::string moved = text;
    const std::string from = dir.file("lib"), to = dir.file("elsewhere/deeper/lib");
    for (std::size_t at = moved.find(from); at != std::string::npos; at = moved.find(from, at))
      moved.replace(at, from.size(), to), at += to.size();
    CHECK(cached_files.at(name) == moved);
  }
  // A mesh changed in the copy is another key: that robot is baked again.
  dir.write("elsewhere/deeper/lib/meshes/palm.stl", to_stl_binary(make_box({0.05, 0.03, 0.01}, 2)));
  from_copy.output_dir = dir.file("out_changed");
  for (const BatchRow& row : bake_robot_batch(copied, from_copy).rows) {
    INFO(row.input.relative);
    if (kGood.count(row.input.relative))
      CHECK(row.outcome ==
            (row.input.relative == "gripper.urdf" ? BatchOutcome::kBaked : BatchOutcome::kCached));
  }
}

TEST_CASE("robot_cache_key: the URDF, its meshes and every result-changing option",
          "[batch][robot]") {
  TempDir dir;
  write_robots(dir);
  const std::string urdf = dir.file("lib/gripper.urdf");
  const UrdfRobot r = read_urdf(urdf);
  const std::string sha = file_sha256(urdf);
  const RobotJob base;
  const std::string key = robot_cache_key(r, sha, base, "gripper.urdf");
  CHECK(key.size() == 64);
  CHECK(robot_cache_key(r, sha, base, "gripper.urdf") == key);
  std::vector<RobotJob> changed(8, base);
  changed[0].bake.request.medial.resolution = 20;
  changed[1].bake.budget.per_link = 3;
  changed[2].bake.outer = false;
  changed[3].formats = {formats::SphereFormat::kCurobo};
  changed[4].set = formats::SphereChoice::kInner;
  changed[5].options_json = "{}";
  changed[6].planner.self_collision.samples = 50;  // the planner request changes the files
  changed[7].planner.tool_frames = {"palm"};
  std::set<std::string> keys = {key};
  for (const RobotJob& j : changed) keys.insert(robot_cache_key(r, sha, j, "gripper.urdf"));
  CHECK(keys.size() == 9);
  RobotJob threads = base;
  threads.bake.request.medial.threads = 3;
  threads.bake.jobs = 2;
  CHECK(robot_cache_key(r, sha, threads, "gripper.urdf") == key);
  // A mesh's bytes change the key; a mesh that cannot be read names the link.
  dir.write("lib/meshes/palm.stl", to_stl_binary(make_box({0.04, 0.03, 0.02}, 2)));
  CHECK(robot_cache_key(r, sha, base, "gripper.urdf") != key);
  fs::remove(dir.file("lib/meshes/palm.stl"));
  CHECK_THROWS_WITH(robot_cache_key(r, sha, base, "gripper.urdf"), Catch::Contains("link 'palm'"));
}

TEST_CASE("robot batch: an output folder that would hold another's is refused before work",
          "[batch][robot]") {
  TempDir dir;
  fs::create_directories(dir.path() / "lib/arm");
  dir.write("lib/arm.urdf", robot("a", urdf_link("a", "<box size=\"1 1 1\"/>")));
  dir.write("lib/arm/hand.urdf", robot("h", urdf_link("h", "<box size=\"1 1 1\"/>")));
  CHECK_THROWS_WITH(
      bake_robot_batch(collect_inputs({dir.file("lib")}, {{"urdf"}, ""}),
                       small_options(dir.file("out"))),
      Catch::Contains("arm.urdf") && Catch::Contains("arm/hand") && Catch::Contains("hold"));
  CHECK_FALSE(fs::exists(dir.file("out")));
}

TEST_CASE("robot batch: a row reports the planner files' summary, baked or from the cache",
          "[batch][robot]") {
  TempDir dir;
  test::write_coarse_arm(dir.path() / "lib/arm");
  const std::vector<BatchInput> inputs = collect_inputs({dir.file("lib")}, {{"urdf"}, ""});
  REQUIRE(inputs.size() == 1);
  RobotBatchOptions o = small_options(dir.file("out"));
  o.robot.planner.self_collision.estimate = 2000;
  o.cache_dir = dir.file("cache");
  const BatchResult baked = bake_robot_batch(inputs, o);
  REQUIRE(baked.count(BatchOutcome::kBaked) == 1);
  const BatchRow& row = baked.rows.front();
  const RobotFileResult alone = bake_robot_file(inputs.front().path, dir.file("alone"), o.robot);
  check_planner_summary(row, alone, test::coarse_arm_links().size());
  // The arm's links two and more joints apart come close: pairs are checked, and the
  // estimate ran over the option's configurations.
  CHECK(row.planner->checked_pairs > 0);
  CHECK(row.planner->estimate_samples == 2000);
  CHECK(row.planner->false_positives <= 2000);
  o.output_dir = dir.file("again");
  const BatchResult cached = bake_robot_batch(inputs, o);
  REQUIRE(cached.count(BatchOutcome::kCached) == 1);
  const BatchRow& copy = cached.rows.front();
  check_planner_summary(copy, alone, test::coarse_arm_links().size());
  // The report's columns: the CSV row's fields after links and spheres.
  const std::string csv = batch_report_csv(cached);
  const std::string line = csv.substr(csv.find("\r\n") + 2);
  const std::string fields = "," + std::to_string(copy.links) + "," + std::to_string(copy.spheres) +
                             "," + copy.planner->default_from + "," +
                             std::to_string(copy.planner->checked_pairs) + ",2000," +
                             std::to_string(copy.planner->false_positives) + "," +
                             std::to_string(copy.planner->false_negatives) + ",";
  CHECK(line.find(fields) != std::string::npos);
  const nlohmann::json report = nlohmann::json::parse(batch_report_json(cached));
  CHECK(report["rows"][0]["checked_pairs"] == copy.planner->checked_pairs);
  CHECK(report["rows"][0]["false_positives"] == copy.planner->false_positives);
}
