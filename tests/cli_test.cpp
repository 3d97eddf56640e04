// The medspheres command-line tool, run as a user runs it: exit codes, output, errors.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/mesh_generators.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/shared_meshes.h"
#include "support/temp_dir.h"

using medspheres::test::CommandResult;
using medspheres::test::run_command;
using medspheres::test::shell_quote;
using medspheres::test::TempDir;
using Catch::Matchers::Contains;

namespace {

CommandResult cli(const std::string& args) {
  return run_command(shell_quote(MEDSPHERES_CLI) + " " + args);
}

const std::string kExample = std::string(MEDSPHERES_SOURCE_DIR) + "/examples/data/knot1.off";

}  // namespace

TEST_CASE("info prints a report and exits 0", "[cli]") {
  const CommandResult r = cli("info " + shell_quote(kExample));
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("triangles           6400"));
  CHECK_THAT(r.out, Contains("closed              yes"));
}

TEST_CASE("info --json has the documented keys and values", "[cli]") {
  const CommandResult r = cli("info --json " + shell_quote(kExample));
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"triangles", "vertices", "components", "boundary_edges",
                          "nonmanifold_edges", "degenerate_triangles", "closed", "volume",
                          "bbox_min", "bbox_max"})
    CHECK(j.contains(key));
  CHECK(j["triangles"] == 6400);
  CHECK(j["vertices"] == 3200);
  CHECK(j["components"] == 1);
  CHECK(j["closed"] == true);
  CHECK(j["boundary_edges"] == 0);
  CHECK(j["volume"].get<double>() == Approx(0.0951747).epsilon(1e-5));  // MANIFEST.tsv
  CHECK(j["bbox_min"].size() == 3);
}

TEST_CASE("info on an open, inward mesh reports and repairs what it can", "[cli]") {
  TempDir dir;
  medspheres::TriangleMesh m = medspheres::make_box({1, 1, 1}, 2);
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  const CommandResult inward = cli("info --json " + shell_quote(dir.write("in.off", medspheres::test::to_off(m))));
  REQUIRE(inward.exit_code == 0);
  const auto j = nlohmann::json::parse(inward.out);
  CHECK(j["components_flipped_outward"] == 1);
  CHECK(j["volume"].get<double>() == Approx(8.0));
  m.triangles.pop_back();
  const CommandResult open = cli("info --json " + shell_quote(dir.write("open.off", medspheres::test::to_off(m))));
  REQUIRE(open.exit_code == 0);
  const auto k = nlohmann::json::parse(open.out);
  CHECK(k["closed"] == false);
  CHECK(k["boundary_edges"] == 3);
}

TEST_CASE("bad usage and bad input exit 2 with a message naming the problem", "[cli]") {
  TempDir dir;
  const std::string missing = dir.file("missing.stl");
  CommandResult r = cli("info " + shell_quote(missing));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains(missing) && Contains("no such file"));

  r = cli("info " + shell_quote(dir.write("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n")));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("nan.off"));

  r = cli("info " + shell_quote(dir.write("x.unknown", "stuff")));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("unsupported mesh format"));

  CHECK(cli("").exit_code == 2);                      // no subcommand
  CHECK(cli("frobnicate").exit_code == 2);            // unknown subcommand
  CHECK(cli("info").exit_code == 2);                  // missing argument
  CHECK(cli("info --bogus " + shell_quote(kExample)).exit_code == 2);
  CHECK(cli("--help").exit_code == 0);
  CHECK(cli("--version").exit_code == 0);
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("info --json agrees with MANIFEST.tsv on every shared mesh", "[cli][shared]") {
  for (const auto& row : medspheres::test::shared_meshes()) {
    INFO(row.file);
    const CommandResult r = cli("info --json " + shell_quote(row.path));
    REQUIRE(r.exit_code == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["closed"] == row.closed);
    CHECK(j["boundary_edges"] == row.boundary_edges);
    CHECK(j["nonmanifold_edges"] == row.nonmanifold_edges);
    CHECK(j["triangles"] == row.triangles);
  }
}
#endif
