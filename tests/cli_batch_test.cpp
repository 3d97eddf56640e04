// medspheres bake over many inputs, run as a user runs it: folders and lists, the report,
// exit codes when some inputs fail, progress lines, shards and the cache.
#include <filesystem>
#include <map>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/mesh/mesh_generators.h"
#include "support/mesh_library.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/sanitizer_build.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// Two good meshes in nested folders and one bad one.
void write_inputs(const TempDir& dir) {
  fs::create_directories(dir.path() / "in/sub");
  dir.write("in/box.off", to_off(make_box({1, 0.5, 0.25}, 2)));
  dir.write("in/sub/ball.stl", to_stl_binary(make_icosphere(1.0, 2)));
  dir.write("in/sub/bad.obj", "v 0 0 0\nf 1 2 3\n");
}

// Every regular file below \p dir but its reports: relative path -> bytes.
std::map<std::string, std::string> outputs(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = e.path().lexically_relative(dir).generic_string();
    if (e.is_regular_file() && rel.rfind("reports/", 0) != 0) out[rel] = read_file(e.path());
  }
  return out;
}

}  // namespace

TEST_CASE("bake FOLDER -o DIR: mirrored outputs, a report, exit 2 for a bad mesh", "[cli][batch]") {
  TempDir dir;
  write_inputs(dir);
  const std::string out = dir.file("out"), report = dir.file("report.json");
  const CommandResult r =
      run_cli("bake " + shell_quote(dir.file("in")) + " -o " + shell_quote(out) +
                  " --resolution 10 --report " + shell_quote(report),
              300);
  CHECK(r.exit_code == 2);
  CHECK(fs::exists(out + "/box.spheres.json"));
  CHECK(fs::exists(out + "/sub/ball.spheres.json"));
  CHECK_FALSE(fs::exists(out + "/sub/bad.spheres.json"));
  // Not a terminal: one plain line per input, and the summary on stdout.
  CHECK_THAT(r.err, Contains("[3/3]") && Contains("failed ") && Contains("bad.obj"));
  CHECK_THAT(r.out, Contains("baked") && Contains("failed"));
  const nlohmann::json j = nlohmann::json::parse(read_file(report));
  REQUIRE(j["rows"].size() == 3);
  CHECK(j["totals"]["baked"] == 2);
  CHECK(j["totals"]["failed"] == 1);
  for (const auto& row : j["rows"]) {
    if (row["relative"] == "sub/bad.obj") {
      CHECK(row["outcome"] == "failed");
      CHECK(row["error"].is_string());
    } else {
      CHECK(row["outcome"] == "baked");
      CHECK(row["spheres"].get<int>() > 0);
      CHECK(row["error"].is_null());
    }
  }
}

TEST_CASE("bake -q batch: a failed input leaves no folder of its own, and says why",
          "[cli][batch]") {
  TempDir dir;
  write_inputs(dir);  // in/sub holds a good and a bad mesh
  fs::create_directories(dir.path() / "in/broken/deeper");
  dir.write("in/broken/deeper/bad.off", "OFF\n3 1 0\n0 0 0\n");
  const std::string out = dir.file("out");
  const CommandResult r = run_cli(
      "bake -q " + shell_quote(dir.file("in")) + " -o " + shell_quote(out) + " --resolution 10",
      300);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err,
             Contains("medspheres: error: failed") && Contains("bad.off") && Contains("bad.obj"));
  CHECK(r.out.empty());
  CHECK(fs::exists(out + "/box.spheres.json"));
  CHECK(fs::exists(out + "/sub/ball.spheres.json"));  // its folder kept: it holds a good one
  CHECK_FALSE(fs::exists(out + "/broken"));
}

TEST_CASE("bake --from-list - with --cache: the second run copies, CSV report", "[cli][batch]") {
  TempDir dir;
  write_inputs(dir);
  const std::string list = dir.write("list.txt", "in/box.off\n# skipped\nin/sub/ball.stl\n");
  const std::string cmd = "cd " + shell_quote(dir.path().string()) + " && " +
                          shell_quote(MEDSPHERES_CLI) +
                          " bake --from-list - -o out --resolution 10 --cache cache --jobs 2 "
                          "--report r.csv < list.txt";
  const CommandResult first = run_command(cmd);
  REQUIRE(first.exit_code == 0);
  CHECK(fs::exists(dir.file("out/in/box.spheres.json")));
  const std::string baked = read_file(dir.file("out/in/sub/ball.spheres.json"));
  CHECK_THAT(read_file(dir.file("r.csv")), Contains("in/box.off,") && Contains(",baked,"));
  fs::remove_all(dir.file("out"));
  const CommandResult second = run_command(cmd);
  REQUIRE(second.exit_code == 0);
  const std::string csv = read_file(dir.file("r.csv"));
  CHECK_THAT(csv, Contains(",cached,"));
  CHECK(csv.find(",baked,") == std::string::npos);
  CHECK(read_file(dir.file("out/in/sub/ball.spheres.json")) == baked);
  (void)list;
}

TEST_CASE("bake batch flags: bad values are exit 2 before any work", "[cli][batch]") {
  TempDir dir;
  write_inputs(dir);
  const std::string in = shell_quote(dir.file("in")), out = shell_quote(dir.file("out"));
  struct Case {
    std::string args, flag;
  };
  const std::string file = dir.write("file.txt", "x");
  for (const Case& c : {Case{in + " -o " + out + " --shard 3/3", "--shard"},
                        Case{in + " -o " + out + " --shard x", "--shard"},
                        Case{in + " -o " + out + " --report r.txt", "--report"},
                        Case{in + " -o " + shell_quote(file), "--output"}, Case{in, "--output"},
                        Case{in + " -o " + out + " --jobs -1", "--jobs"},
                        Case{in + " -o " + out + " --cache " + shell_quote(file), "--cache"},
                        Case{in + " -o " + out + " --cache ''", "--cache"},
                        Case{in + " -o " + out + " --shard ''", "--shard"},
                        Case{in + " -o " + out + " --report ''", "--report"}}) {
    INFO(c.args);
    const CommandResult r = run_cli("bake " + c.args, 60);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(c.flag));
    CHECK_FALSE(fs::exists(dir.file("out")));
  }
}

TEST_CASE("the Slurm example's array tasks, one after another, give the unsharded files",
          "[cli][batch]") {
  TempDir dir;
  write_mesh_library(dir.file("assets"), 9, 5, 100, 1200);
  const CommandResult whole = run_cli("bake -q " + shell_quote(dir.file("assets")) + " -o " +
                                          shell_quote(dir.file("whole")) + " --resolution 10",
                                      600);
  REQUIRE(whole.exit_code == 0);
  const auto expected = outputs(dir.file("whole"));
  REQUIRE(expected.size() == 9);
  const std::string script = std::string(MEDSPHERES_SOURCE_DIR) + "/examples/batch/slurm_bake.sh";
  for (int k = 0; k < 3; ++k) {
    const CommandResult task = run_command(
        "env ASSETS=" + shell_quote(dir.file("assets")) + " OUT=" + shell_quote(dir.file("out")) +
        " CACHE=" + shell_quote(dir.file("cache")) + " MEDSPHERES=" + shell_quote(MEDSPHERES_CLI) +
        " SLURM_ARRAY_TASK_ID=" + std::to_string(k + 4) +
        " SLURM_ARRAY_TASK_MIN=4 SLURM_ARRAY_TASK_COUNT=3 bash " + shell_quote(script) +
        " -q --resolution 10");
    INFO(task.err);
    REQUIRE(task.exit_code == 0);
    CHECK(fs::exists(dir.file("out/reports/shard-" + std::to_string(k) + "-of-3.json")));
  }
  CHECK(outputs(dir.file("out")) == expected);
}

TEST_CASE(
    "robot FOLDER -o DIR: a folder per robot, a CSV report, exit 2 for a broken URDF, "
    "the cache",
    "[cli][batch][robot]") {
  TempDir dir;
  fs::create_directories(dir.path() / "robots/arm/meshes");
  dir.write("robots/arm/meshes/ball.obj", to_obj(make_icosphere(0.05, 1)));
  dir.write("robots/arm/arm.urdf",
            "<robot name=\"arm\"><link name=\"base\"><collision><geometry><box size=\"0.2 0.1 "
            "0.05\"/></geometry></collision></link><link name=\"ball\"><collision><geometry>"
            "<mesh filename=\"meshes/ball.obj\"/></geometry></collision></link><joint name=\"j\" "
            "type=\"fixed\"><parent link=\"base\"/><child link=\"ball\"/></joint></robot>\n");
  dir.write("robots/pole.urdf",
            "<robot name=\"pole\"><link name=\"pole\"><collision><geometry><cylinder "
            "radius=\"0.02\" length=\"0.3\"/></geometry></collision></link></robot>\n");
  dir.write("robots/broken.urdf", "<robot name=\"broken\"><link name=\"a\">\n");
  // No covering sets in the sanitizer builds, where their bakes took most of the time (the
  // robot tests bake covers there); the comparisons hold for either set.
  const std::string sets = medspheres::test::kSanitizerBuild ? " --no-outer" : "";
  const std::string cmd =
      "robot " + shell_quote(dir.file("robots")) + " -o " + shell_quote(dir.file("out")) +
      " --spheres-per-link 4 --resolution 12" + sets + " --format robot,curobo --cache " +
      shell_quote(dir.file("cache")) + " --jobs 2 --report " + shell_quote(dir.file("r.csv"));
  const CommandResult first = run_cli(cmd, 600);
  CHECK(first.exit_code == 2);
  CHECK_THAT(first.err, Contains("[3/3]") && Contains("broken.urdf") && Contains("(2 links, "));
  // The progress line counts in the singular for one: the pole has one link.
  CHECK_THAT(first.err, Contains("pole.urdf") && Contains("(1 link, "));
  CHECK(first.err.find("(1 links") == std::string::npos);
  CHECK(fs::exists(dir.file("out/arm/arm/arm.robot.json")));
  CHECK(fs::exists(dir.file("out/arm/arm/arm.curobo.yml")));
  CHECK(fs::exists(dir.file("out/pole/pole.robot.json")));
  CHECK_FALSE(fs::exists(dir.file("out/broken")));
  const std::string csv = read_file(dir.file("r.csv"));
  CHECK_THAT(csv, Contains("input,relative,output,outcome,links,spheres,default_from,"
                           "checked_pairs,estimate_samples,false_positives,false_negatives,"
                           "seconds,error") &&
                      Contains("arm/arm.urdf,") && Contains(",baked,2,") &&
                      Contains("broken.urdf,") && Contains(",failed,0,0,,,,,,"));
  // The pole (one link) has no pair to check: its planner fields say so, no estimate made.
  CHECK_THAT(csv, Contains(",baked,1,") && Contains(",zero,0,0,0,0,"));
  CHECK_THAT(first.err, Contains("default zero, 0 pairs checked"));
  const auto baked = outputs(dir.file("out"));
  fs::remove_all(dir.file("out"));
  const CommandResult second = run_cli(cmd, 600);
  CHECK(second.exit_code == 2);
  CHECK_THAT(read_file(dir.file("r.csv")), Contains(",cached,2,") && Contains(",cached,1,"));
  CHECK(outputs(dir.file("out")) == baked);
  // The Slurm example's tasks with COMMAND=robot, one after another: the same folders.
  fs::remove(dir.file("robots/broken.urdf"));
  const std::string script = std::string(MEDSPHERES_SOURCE_DIR) + "/examples/batch/slurm_bake.sh";
  for (int k = 0; k < 2; ++k) {
    const CommandResult task = run_command(
        "env COMMAND=robot ASSETS=" + shell_quote(dir.file("robots")) +
        " OUT=" + shell_quote(dir.file("slurm")) + " CACHE=" + shell_quote(dir.file("cache2")) +
        " MEDSPHERES=" + shell_quote(MEDSPHERES_CLI) + " SLURM_ARRAY_TASK_ID=" + std::to_string(k) +
        " SLURM_ARRAY_TASK_COUNT=2 bash " + shell_quote(script) +
        " -q --spheres-per-link 4 --resolution 12 --format robot,curobo" + sets);
    INFO(task.err);
    CHECK(task.exit_code == 0);
  }
  CHECK(outputs(dir.file("slurm")) == baked);
  // One URDF with --jobs alone is still one robot into -o itself.
  const CommandResult one =
      run_cli("robot -q " + shell_quote(dir.file("robots/pole.urdf")) + " -o " +
                  shell_quote(dir.file("one")) + " --spheres-per-link 4 --resolution 12 --jobs 2",
              300);
  CHECK(one.exit_code == 0);
  CHECK(fs::exists(dir.file("one/pole.robot.json")));
}
