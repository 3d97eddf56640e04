// medspheres eval, run as a user runs it: output, JSON keys, exit codes.
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/io.h"
#include "medspheres/mesh/mesh_generators.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using namespace medspheres::test;
using Catch::Matchers::Contains;

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;
const std::string kEightMesh = medspheres::test::example_mesh("eight.off");
const std::string kFast = " --samples 100000 --surface-samples 5000";

CommandResult eval(const std::string& args) {
  return medspheres::test::run_cli("eval " + args);
}

// A [-1, 1]^3 box mesh, closed or with one triangle missing.
std::string write_box(const TempDir& dir, bool open) {
  medspheres::TriangleMesh m = medspheres::make_box({1.0, 1.0, 1.0}, 2);
  if (open) m.triangles.pop_back();
  return dir.write(open ? "open_box.off" : "box.off", medspheres::test::to_off(m));
}

// Everything but the timings.
nlohmann::json without_seconds(nlohmann::json j) {
  j.erase("seconds");
  j.erase("seconds_by_part");
  return j;
}

}  // namespace

TEST_CASE("eval of a baked set: text summary, JSON keys, exact nerr as bake wrote it",
          "[cli][eval]") {
  TempDir dir;
  const std::string spheres = dir.file("eight.json");
  REQUIRE(run_command(shell_quote(MEDSPHERES_CLI) + " bake -q " + shell_quote(kEightMesh) + " -o " +
                      shell_quote(spheres) + " --resolution 20")
              .exit_code == 0);
  const auto baked = nlohmann::json::parse(medspheres::load_sphere_set(spheres).metadata_json);

  const CommandResult text = eval(shell_quote(kEightMesh) + " " + shell_quote(spheres) + kFast);
  REQUIRE(text.exit_code == 0);
  CHECK_THAT(text.out, Contains("nerr") && Contains("exact") && Contains("Monte Carlo") &&
                           Contains("uncovered"));

  const CommandResult r =
      eval(shell_quote(kEightMesh) + " " + shell_quote(spheres) + kFast + " --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"spheres", "mesh_volume", "union_volume", "union_area", "nerr",
                          "nerr_kind", "max_protrusion", "mc_error", "uncovered_max",
                          "uncovered_mean", "uncovered_p95", "seconds"})
    CHECK(j.contains(key));
  for (const char* key : {"estimate", "lo", "hi"}) CHECK(j["mc_error"].contains(key));
  CHECK(j["spheres"] == baked["stats"]["count"]);
  CHECK(j["nerr_kind"] == "exact");
  CHECK(j["nerr"].get<double>() == Approx(baked["stats"]["nerr"].get<double>()).epsilon(1e-12));
  CHECK(j["max_protrusion"].get<double>() <= 0.0);
  const double estimate = j["mc_error"]["estimate"], sigma = j["mc_error"]["sigma"];
  CHECK(std::abs(estimate - j["nerr"].get<double>()) <= 4.0 * sigma);
  CHECK(j["mc_error"]["lo"].get<double>() <= estimate);
  CHECK(j["mc_error"]["hi"].get<double>() >= estimate);
  CHECK(j["uncovered_max"].get<double>() >= j["uncovered_p95"].get<double>());
  CHECK(j["uncovered_p95"].get<double>() >= 0.0);
  CHECK(j["warnings"].empty());
}

TEST_CASE("eval of a set sticking out of a box: protrusion and a lower bound", "[cli][eval]") {
  TempDir dir;
  const std::string box = write_box(dir, false);
  const std::string spheres =
      dir.write("out.json", R"({"spheres": [[0.8, 0, 0, 0.5], [-0.5, 0, 0, 0.3]]})");
  const CommandResult r = eval(shell_quote(box) + " " + shell_quote(spheres) + kFast + " --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["nerr_kind"] == "lower_bound");
  CHECK(j["max_protrusion"].get<double>() == Approx(0.3).epsilon(1e-12));
  CHECK(j["max_protrusion_sphere"] == 0);
  CHECK(j["mesh_volume"].get<double>() == Approx(8.0).epsilon(1e-14));
  const double u = 4.0 / 3.0 * kPi * (0.125 + 0.027);
  CHECK(j["nerr"].get<double>() == Approx((8.0 - u) / 8.0).epsilon(1e-12));
  const CommandResult text = eval(shell_quote(box) + " " + shell_quote(spheres) + kFast);
  CHECK_THAT(text.out, Contains("lower bound"));
}

TEST_CASE("eval of an open mesh says what is not defined", "[cli][eval]") {
  TempDir dir;
  const std::string open = write_box(dir, true);
  const std::string spheres = dir.write("in.json", R"({"spheres": [[0, 0, 0, 0.8]]})");
  const CommandResult r = eval(shell_quote(open) + " " + shell_quote(spheres) + kFast + " --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["mesh_closed"] == false);
  CHECK(j["mesh_volume"].is_null());
  CHECK(j["nerr"].is_null());
  CHECK(j["nerr_kind"] == "undefined");
  CHECK(j["mc_error"]["normalized_by"] == "winding_solid_volume_estimate");
  CHECK(j["mc_error"]["estimate"].is_number());
  const CommandResult text = eval(shell_quote(open) + " " + shell_quote(spheres) + kFast);
  REQUIRE(text.exit_code == 0);
  CHECK_THAT(text.out, Contains("open: its volume, and so nerr, is not defined") &&
                           Contains("winding-number solid"));
}

TEST_CASE("eval gives the same numbers for every thread count", "[cli][eval]") {
  TempDir dir;
  const std::string box = write_box(dir, false);
  const std::string spheres = dir.write(
      "s.json", R"({"spheres": [[0.8, 0, 0, 0.5], [-0.5, 0.1, 0, 0.6], [0, 0, 0.9, 0.3]]})");
  const std::string args = shell_quote(box) + " " + shell_quote(spheres) + kFast + " --json";
  const CommandResult one = eval(args + " --threads 1");
  const CommandResult two = eval(args + " --threads 2");
  REQUIRE(one.exit_code == 0);
  REQUIRE(two.exit_code == 0);
  CHECK(without_seconds(nlohmann::json::parse(one.out)) ==
        without_seconds(nlohmann::json::parse(two.out)));
  const CommandResult seeded = eval(args + " --seed 99");
  CHECK(nlohmann::json::parse(seeded.out)["mc_error"]["seed"] == 99);
}

TEST_CASE("eval rejects bad input with exit 2 and names the file or option", "[cli][eval]") {
  TempDir dir;
  const std::string box = write_box(dir, false);
  const std::string spheres = dir.write("s.json", R"({"spheres": [[0, 0, 0, 0.5]]})");
  const std::string both = shell_quote(box) + " " + shell_quote(spheres);
  for (const std::string option : {"--samples", "--surface-samples", "--threads"}) {
    INFO(option);
    const std::string bad = option == "--threads" ? " -1" : " 0";
    const CommandResult r = eval(both + " " + option + bad);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(option));
  }
  // Counts whose points would not fit in memory: refused at once, naming the option.
  for (const std::string too_many : {" --samples 10000000001", " --surface-samples 100000001",
                                     " --surface-samples 99999999999"}) {
    INFO(too_many);
    const CommandResult r = eval(both + too_many);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(too_many.substr(1, too_many.find(' ', 1) - 1)) && Contains("1 .. "));
  }
  CHECK(eval(both + " --samples -5").exit_code == 2);
  CHECK(eval(both + " --samples many").exit_code == 2);
  CHECK(eval(both + " --seed -1").exit_code == 2);
  CHECK(eval(shell_quote(box)).exit_code == 2);  // no sphere file

  const std::string missing = dir.file("missing.json");
  CommandResult r = eval(shell_quote(box) + " " + shell_quote(missing));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains(missing));
  r = eval(shell_quote(dir.file("missing.off")) + " " + shell_quote(spheres));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("missing.off"));
  const std::string broken = dir.write("broken.json", "{\"spheres\": [[0, 0, 0");
  r = eval(shell_quote(box) + " " + shell_quote(broken));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("broken.json"));
  const std::string empty = dir.write("empty.json", R"({"spheres": []})");
  r = eval(shell_quote(box) + " " + shell_quote(empty));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("empty.json") && Contains("no spheres"));
  const std::string negative = dir.write("negative.json", R"({"spheres": [[0, 0, 0, -1]]})");
  r = eval(shell_quote(box) + " " + shell_quote(negative));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("negative.json"));
}

TEST_CASE("eval --solid: the solid the file records, or the one named", "[cli][eval]") {
  TempDir dir;
  const std::string box = write_box(dir, false);
  // One ball, recorded as baked from the robust solid at resolution 16.
  const std::string spheres = dir.write("s.json", R"({"spheres": [[0, 0, 0, 0.5]],
        "stats": {"solid": "robust", "robust_resolution": 16, "robust_thickness": 0}})");
  const std::string both = shell_quote(box) + " " + shell_quote(spheres) + kFast + " --json";
  CommandResult r = eval(both);
  REQUIRE(r.exit_code == 0);
  auto j = nlohmann::json::parse(r.out);
  CHECK(j["solid"] == "robust");
  CHECK(j["robust_resolution"] == 16);
  // the robust solid holds the box (volume 8) and lies within 0.46 of it (h = 1/8,
  // r = (1 + sqrt(3)/2) h, r + sqrt(3) h < 0.45): its volume is between 8 and 2.9^3
  CHECK(j["mesh_volume"].get<double>() > 8.0);
  CHECK(j["mesh_volume"].get<double>() < 2.9 * 2.9 * 2.9);
  CHECK_THAT(j["warnings"].dump(), Contains("robust solid at resolution 16"));
  r = eval(both + " --solid winding");
  REQUIRE(r.exit_code == 0);
  j = nlohmann::json::parse(r.out);
  CHECK(j["solid"] == "winding");
  CHECK(j["mesh_volume"].get<double>() == Approx(8.0).epsilon(1e-14));
  r = eval(both + " --solid robust --robust-resolution 24");
  REQUIRE(r.exit_code == 0);
  CHECK(nlohmann::json::parse(r.out)["robust_resolution"] == 24);
  // nonsense is named before any work
  r = eval(both + " --solid robst");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--solid"));
  r = eval(both + " --robust-thickness -1");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--robust-thickness"));
  // a robot's links have no solid to choose: the flag is refused, not ignored
  const std::string urdf = dir.write("r.urdf", "<robot name=\"r\"><link name=\"a\"/></robot>");
  r = eval(shell_quote(urdf) + " " + shell_quote(spheres) + " --solid robust");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--solid") && Contains("robot"));
}
