// medspheres bake over many inputs, run as a user runs it: folders and lists, the report,
// exit codes when some inputs fail, progress lines, shards and the cache.
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/mesh/mesh_generators.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
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

TEST_CASE("bake --from-list - with --cache: the second run copies; CSV report", "[cli][batch]") {
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
                        Case{in + " -o " + out + " --jobs -1", "--jobs"}}) {
    INFO(c.args);
    const CommandResult r = run_cli("bake " + c.args, 60);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(c.flag));
    CHECK_FALSE(fs::exists(dir.file("out")));
  }
}
