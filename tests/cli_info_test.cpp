// medspheres info, and eval and bake on a self-intersecting mesh, run as a user runs them.
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/io.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/sphere_set.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using namespace medspheres::test;
using Catch::Matchers::Contains;

namespace {

const std::string kEight = medspheres::test::example_mesh("eight.off");

// Two [-1, 1]^3 boxes, the second moved by (1, 0.3, 0.2): their faces cross.
std::string write_crossing_boxes(const TempDir& dir) {
  medspheres::TriangleMesh m = medspheres::make_box({1.0, 1.0, 1.0});
  const medspheres::TriangleMesh b = m;
  const int base = static_cast<int>(m.vertices.size());
  for (const Eigen::Vector3d& v : b.vertices)
    m.vertices.push_back(v + Eigen::Vector3d(1, 0.3, 0.2));
  for (const auto& t : b.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return dir.write("crossing.off", medspheres::test::to_off(m));
}

}  // namespace

TEST_CASE("info reports self-intersecting triangle pairs, text and JSON", "[cli][info]") {
  TempDir dir;
  const std::string crossing = write_crossing_boxes(dir);
  const CommandResult j = run_cli("info --json " + shell_quote(crossing));
  REQUIRE(j.exit_code == 0);
  const auto info = nlohmann::json::parse(j.out);
  const std::size_t pairs = info["self_intersecting_pairs"];
  CHECK(pairs > 0);
  CHECK(info["closed"] == true);
  CHECK(info["components"] == 2);
  const CommandResult text = run_cli("info " + shell_quote(crossing));
  REQUIRE(text.exit_code == 0);
  CHECK_THAT(text.out, Contains("self-intersecting   " + std::to_string(pairs) + " triangle pair"));
  CHECK_THAT(text.out, Contains("the surface intersects itself"));

  const CommandResult clean = run_cli("info --json " + shell_quote(kEight));
  REQUIRE(clean.exit_code == 0);
  CHECK(nlohmann::json::parse(clean.out)["self_intersecting_pairs"] == 0);
  CHECK_THAT(run_cli("info " + shell_quote(kEight)).out, Contains("self-intersecting   no"));
}

TEST_CASE("eval on a self-intersecting mesh: nerr approximate, a warning names the pairs",
          "[cli][info][eval]") {
  TempDir dir;
  const std::string crossing = write_crossing_boxes(dir);
  const std::size_t pairs = nlohmann::json::parse(
      run_cli("info --json " + shell_quote(crossing)).out)["self_intersecting_pairs"];
  medspheres::SphereSet set;
  set.spheres = {{Eigen::Vector3d(0, 0, 0), 0.5}};
  const std::string spheres = dir.file("one.json");
  medspheres::save_sphere_set(set, spheres);
  const std::string args =
      shell_quote(crossing) + " " + shell_quote(spheres) + " --samples 20000 --surface-samples 500";

  const CommandResult r = run_cli("eval --json " + args);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["nerr_kind"] == "approximate");
  CHECK(j["self_intersecting_pairs"] == pairs);
  CHECK(j["nerr"].get<double>() > 0.0);
  bool named = false;
  for (const auto& w : j["warnings"])
    named |= w.get<std::string>().find("self-intersects: " + std::to_string(pairs) + " pair") !=
             std::string::npos;
  CHECK(named);

  const CommandResult text = run_cli("eval " + args);
  REQUIRE(text.exit_code == 0);
  CHECK_THAT(text.out, Contains("approximate: the mesh intersects itself") &&
                           Contains("warning: the mesh self-intersects"));
}

TEST_CASE("bake --target-error on a self-intersecting mesh says its nerr is approximate",
          "[cli][info][bake]") {
  TempDir dir;
  const std::string crossing = write_crossing_boxes(dir);
  const std::string out = dir.file("t.json");
  const CommandResult r =
      run_cli("bake " + shell_quote(crossing) + " -o " + shell_quote(out) + " --target-error 0.5");
  REQUIRE(r.exit_code == 0);
  const auto stats = nlohmann::json::parse(medspheres::load_sphere_set(out).metadata_json)["stats"];
  CHECK(stats["nerr_kind"] == "approximate");
  CHECK(stats["nerr"].get<double>() <= 0.5);
  CHECK_THAT(r.out, Contains("chosen for target_error 0.5") &&
                        Contains("(by an approximate nerr: the mesh intersects itself)") &&
                        Contains("self-intersecting ("));
}
