// The medspheres command-line tool, run as a user runs it: exit codes, output, errors.
#include <algorithm>
#include <filesystem>

#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"

#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/sha256.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/shared_meshes.h"
#include "support/temp_dir.h"

using Catch::Matchers::Contains;
using medspheres::test::CommandResult;
using medspheres::test::read_file;
using medspheres::test::run_command;
using medspheres::test::shell_quote;
using medspheres::test::TempDir;

namespace {

CommandResult cli(const std::string& args) {
  return medspheres::test::run_cli(args);
}

const std::string kExample = medspheres::test::example_mesh("knot1.off");

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
  for (const char* key :
       {"triangles", "vertices", "components", "boundary_edges", "nonmanifold_edges",
        "degenerate_triangles", "closed", "volume", "bbox_min", "bbox_max"})
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
  const CommandResult inward =
      cli("info --json " + shell_quote(dir.write("in.off", medspheres::test::to_off(m))));
  REQUIRE(inward.exit_code == 0);
  const auto j = nlohmann::json::parse(inward.out);
  CHECK(j["components_flipped_outward"] == 1);
  CHECK(j["volume"].get<double>() == Approx(8.0));
  m.triangles.pop_back();
  const CommandResult open =
      cli("info --json " + shell_quote(dir.write("open.off", medspheres::test::to_off(m))));
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

  r = cli("info " +
          shell_quote(dir.write("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n")));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("nan.off") && Contains("non-finite"));

  // A FIFO would block open() for ever.
  const std::string fifo = dir.file("fifo.obj");
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  r = cli("info " + shell_quote(fifo));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("fifo.obj") && Contains("not a regular file"));

  r = cli("info " + shell_quote(dir.write("x.unknown", "stuff")));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("unsupported mesh format"));

  CHECK(cli("").exit_code == 2);            // no subcommand
  CHECK(cli("frobnicate").exit_code == 2);  // unknown subcommand
  CHECK(cli("info").exit_code == 2);        // missing argument
  CHECK(cli("info --bogus " + shell_quote(kExample)).exit_code == 2);
  CHECK(cli("--help").exit_code == 0);
  CHECK(cli("--version").exit_code == 0);
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("info --json agrees with MANIFEST.tsv on every shared mesh", "[cli][shared]") {
  const auto& rows = medspheres::test::shared_meshes();
  REQUIRE(rows.size() >= 40);  // an empty or unreadable manifest must not pass
  for (const auto& row : rows) {
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

namespace {
const std::string kEight = medspheres::test::example_mesh("eight.off");
}  // namespace

TEST_CASE("bake writes a valid sphere-set file with provenance", "[cli][bake]") {
  TempDir dir;
  const std::string out = dir.file("eight.spheres.json");
  const CommandResult r =
      cli("bake " + shell_quote(kEight) + " -o " + shell_quote(out) + " --resolution 24");
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("spheres") && Contains("nerr"));
  const medspheres::SphereSet set = medspheres::load_sphere_set(out);
  CHECK(set.size() > 10);
  const auto meta = nlohmann::json::parse(set.metadata_json);
  CHECK(meta["source"]["sha256"] == medspheres::file_sha256(kEight));
  CHECK(meta["source"]["triangles"] == 634);
  CHECK(meta["generator"]["method"] == "medial");
  CHECK(meta["generator"]["params"]["resolution"] == 24);
  CHECK(meta["stats"]["count"] == set.size());
  CHECK(meta["stats"]["nerr_kind"] == "exact");
  CHECK(meta["stats"]["nerr"].get<double>() > 0.0);
  CHECK(meta["stats"]["nerr"].get<double>() < 0.5);
}

TEST_CASE("bake's default output is the mesh stem in the working directory", "[cli][bake]") {
  TempDir dir;
  const CommandResult r =
      run_command("cd " + shell_quote(dir.path().string()) + " && " + shell_quote(MEDSPHERES_CLI) +
                  " bake --quiet " + shell_quote(kEight));
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.empty());  // --quiet
  CHECK(medspheres::load_sphere_set(dir.file("eight.spheres.json")).size() > 0);
}

TEST_CASE("bake's sphere budget and error target are honoured", "[cli][bake]") {
  TempDir dir;
  const std::string out = dir.file("k.json");
  REQUIRE(cli("bake -q " + shell_quote(kExample) + " -o " + shell_quote(out) + " --max-spheres 120")
              .exit_code == 0);
  const medspheres::SphereSet capped = medspheres::load_sphere_set(out);
  CHECK(capped.size() <= 120);
  CHECK(nlohmann::json::parse(capped.metadata_json)["generator"]["params"]["mode"] ==
        "max_spheres");

  REQUIRE(
      cli("bake -q " + shell_quote(kExample) + " -o " + shell_quote(out) + " --target-error 0.08")
          .exit_code == 0);
  const auto meta = nlohmann::json::parse(medspheres::load_sphere_set(out).metadata_json);
  CHECK(meta["stats"]["nerr"].get<double>() <= 0.08);
}

TEST_CASE("bake rejects nonsense with exit 2 and leaves no output behind", "[cli][bake]") {
  TempDir dir;
  const std::string out = dir.file("out.json");
  const std::string existing = dir.write("existing.json", "keep me");
  for (const std::string bad : {"--resolution 0",
                                "--resolution -3",
                                "--resolution x",
                                "--object-angle -0.5",
                                "--object-angle 3.5",
                                "--medial-tolerance -1",
                                "--threads -2",
                                "--max-spheres 0",
                                "--target-error 0",
                                "--target-error 1.5",
                                "--max-spheres 10 --target-error 0.1",
                                "--vertex-tolerance 0.01",
                                "--dilate --vertex-tolerance 0",
                                "--dilate --vertex-tolerance -1",
                                "--dilate --max-protrusion -0.1",
                                "--max-protrusion 0.1",
                                "--cover 0",
                                "--cover -1",
                                "--dilate --seed x",
                                "--dilate --seed -1",
                                "--robust-resolution 5",
                                "--robust-resolution -1",
                                "--cover 0.003x",
                                "--cover L",
                                "--cover -0.001L",
                                "--cover 0L",
                                "--dilate --max-protrusion nanL",
                                "--dilate --vertex-tolerance 1e400L"}) {
    INFO(bad);
    const CommandResult r =
        cli("bake -q " + shell_quote(kEight) + " -o " + shell_quote(out) + " " + bad);
    CHECK(r.exit_code == 2);
    CHECK_FALSE(std::filesystem::exists(out));
    const CommandResult keep =
        cli("bake -q " + shell_quote(kEight) + " -o " + shell_quote(existing) + " " + bad);
    CHECK(keep.exit_code == 2);
    CHECK(read_file(existing) == "keep me");
  }
  // A mesh with no interior: an error naming the problem, no file.
  const std::string sheet =
      dir.write("sheet.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  const CommandResult r = cli("bake " + shell_quote(sheet) + " -o " + shell_quote(out));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("the mesh bounds no volume"));
  CHECK_FALSE(std::filesystem::exists(out));
  CHECK(cli("bake " + shell_quote(dir.file("missing.obj")) + " -o " + shell_quote(out)).exit_code ==
        2);
  // Only the pre-existing file remains in the directory: no temporaries.
  std::size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    entries += e.path() != sheet;
  CHECK(entries == 1);
}

TEST_CASE("bake refuses an output named for another sphere format", "[cli][bake]") {
  TempDir dir;
  for (const std::string name : {"arm.yml", "arm.yaml", "arm.xrdf", "arm.urdf", "arm.srdf",
                                 "arm.sph", "arm.robot.json", "arm.foam.json"}) {
    INFO(name);
    const std::string out = dir.file(name);
    const CommandResult r = cli("bake -q " + shell_quote(kEight) + " -o " + shell_quote(out));
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains("--output") && Contains(name) && Contains("medspheres convert"));
    CHECK_FALSE(std::filesystem::exists(out));
  }
  // A name that no format claims is written as a sphere set, as a .json is.
  const std::string text = dir.file("arm.txt");
  REQUIRE(cli("bake -q " + shell_quote(kEight) + " -o " + shell_quote(text)).exit_code == 0);
  CHECK(medspheres::load_sphere_set(text).size() > 0);
}

TEST_CASE("bake --dilate writes S+ and records the dilation", "[cli][bake]") {
  TempDir dir;
  const std::string internal = dir.file("sd.json"), dilated = dir.file("splus.json");
  REQUIRE(cli("bake -q " + shell_quote(kEight) + " -o " + shell_quote(internal)).exit_code == 0);
  const CommandResult r =
      cli("bake " + shell_quote(kEight) + " -o " + shell_quote(dilated) + " --dilate --cover 0.01");
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("dilated") && Contains("protrusion"));
  const medspheres::SphereSet sd = medspheres::load_sphere_set(internal);
  const medspheres::SphereSet plus = medspheres::load_sphere_set(dilated);
  REQUIRE(plus.size() >= sd.size());
  for (std::size_t i = 0; i < sd.size(); ++i) {
    CHECK(plus.spheres[i].center == sd.spheres[i].center);
    CHECK(plus.spheres[i].radius >= sd.spheres[i].radius);
  }
  const auto meta = nlohmann::json::parse(plus.metadata_json);
  CHECK(meta["generator"]["method"] == "medial+dilation");
  CHECK(meta["generator"]["params"]["dilation"]["cover_tolerance"] == 0.01);
  CHECK(meta["stats"]["count"] == plus.size());
  CHECK(meta["stats"]["dilation"]["input_spheres"] == sd.size());
  CHECK(meta["stats"]["nerr_kind"] == "lower_bound");
  CHECK(meta["stats"]["max_protrusion"].get<double>() > 0.0);

  // Lengths may be given as multiples of the bounding box's largest side L.
  const std::string relative = dir.file("relative.json");
  REQUIRE(cli("bake -q " + shell_quote(kEight) + " -o " + shell_quote(relative) +
              " --dilate --max-protrusion 0.002L --cover 0.003L --vertex-tolerance 0.01L")
              .exit_code == 0);
  const auto rel = nlohmann::json::parse(medspheres::load_sphere_set(relative).metadata_json);
  const auto& bmin = rel["source"]["bbox_min"];
  const auto& bmax = rel["source"]["bbox_max"];
  double longest = 0.0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(longest, bmax[k].get<double>() - bmin[k].get<double>());
  const auto& d = rel["generator"]["params"]["dilation"];
  CHECK(d["max_protrusion"].get<double>() == Approx(0.002 * longest));
  CHECK(d["cover_tolerance"].get<double>() == Approx(0.003 * longest));
  CHECK(d["vertex_tolerance"].get<double>() == Approx(0.01 * longest));
  CHECK(rel["stats"]["max_protrusion"].get<double>() <= 0.002 * longest * (1 + 1e-9));
}
