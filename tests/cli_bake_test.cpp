// medspheres bake (and eval) at the edges of their options, run as a user runs them:
// exit codes, messages, what the written file says, and what happens to the output path.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

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

const std::string kKnot = medspheres::test::example_mesh("knot1.off");
const std::string kEight = medspheres::test::example_mesh("eight.off");

CommandResult cli(const std::string& args, int seconds = 300) {
  return run_cli(args, seconds);
}

nlohmann::json stats_of(const std::string& path) {
  return nlohmann::json::parse(medspheres::load_sphere_set(path).metadata_json)["stats"];
}

// Bakes kKnot at a resolution into \p out; returns its stats.
nlohmann::json bake_knot_at(int resolution, const std::string& out) {
  const CommandResult r = cli("bake -q " + shell_quote(kKnot) + " -o " + shell_quote(out) +
                              " --resolution " + std::to_string(resolution));
  REQUIRE(r.exit_code == 0);
  return stats_of(out);
}

}  // namespace

TEST_CASE("bake --medial-tolerance outside its range: exit 2 naming the range", "[cli][bake]") {
  TempDir dir;
  const std::string out = dir.file("t.json");
  // 1e-18 is below the double spacing, which no bisection gets under; 1e300, 10 and 0.5
  // are a cell or more, which no longer says which cell a medial point is in.
  for (const std::string t : {"1e-18", "1e-10", "1e300", "10", "0.5", "0.0358"}) {
    INFO(t);
    const CommandResult r = cli(
        "bake -q " + shell_quote(kKnot) + " -o " + shell_quote(out) + " --medial-tolerance " + t,
        120);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains("--medial-tolerance") && Contains("must be in [1e-09, 0.0357143)") &&
                          Contains("cell size"));
    CHECK_FALSE(std::filesystem::exists(out));
  }
  // A search bakes up to resolution 512: the tolerance must be below that cell.
  const CommandResult search = cli("bake -q " + shell_quote(kKnot) + " -o " + shell_quote(out) +
                                   " --max-spheres 100 --medial-tolerance 0.01");
  CHECK(search.exit_code == 2);
  CHECK_THAT(search.err, Contains("--medial-tolerance") && Contains("512"));
  // The ends of the range work, and end.
  for (const std::string t : {"1e-9", "0.035"}) {
    INFO(t);
    const CommandResult r = cli(
        "bake -q " + shell_quote(kKnot) + " -o " + shell_quote(out) + " --medial-tolerance " + t,
        120);
    CHECK(r.exit_code == 0);
    CHECK(stats_of(out)["nerr_kind"] == "exact");
  }
}

TEST_CASE("bake and eval cap --threads at 1024", "[cli][bake]") {
  // More threads than the system can create would crash the OpenMP runtime.
  TempDir dir;
  const std::string spheres = dir.write("s.json", R"({"spheres": [[0, 0, 0, 0.05]]})");
  for (const std::string n : {"1025", "100000"}) {
    INFO(n);
    CommandResult r = cli("bake -q " + shell_quote(kEight) + " -o " +
                          shell_quote(dir.file("o.json")) + " --threads " + n);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains("--threads") && Contains("[0, 1024]"));
    r = cli("eval " + shell_quote(kEight) + " " + shell_quote(spheres) + " --threads " + n);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains("--threads") && Contains("[0, 1024]"));
  }
  CHECK_FALSE(std::filesystem::exists(dir.file("o.json")));
}

TEST_CASE("eval of a set with a subnormal radius works", "[cli][eval]") {
  // A subnormal radius (1e-320) must not make a degenerate cell of eval's grid over the
  // spheres.
  TempDir dir;
  for (const std::string set : {R"({"spheres": [[0, 0, 0, 1e-320]]})",
                                R"({"spheres": [[0.1, 0, 0, 1e-320], [0, 0, 0, 0.05]]})"}) {
    INFO(set);
    const std::string spheres = dir.write("tiny.json", set);
    const CommandResult r = cli("eval --json --samples 20000 --surface-samples 2000 " +
                                shell_quote(kKnot) + " " + shell_quote(spheres));
    REQUIRE(r.exit_code == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["nerr"].get<double>() > 0.9);
    CHECK(j["uncovered_max"].get<double>() > 0.0);
  }
}

TEST_CASE("bake --max-spheres gives the best N inner spheres", "[cli][bake]") {
  TempDir dir;
  const std::string out = dir.file("k.json");
  // Small and exact budgets: exactly N spheres where the medial set has that many (the
  // resolution search of old stopped at 2 spheres for 5, found none for 1, and 100 only by
  // looking past 13), every one inside (nerr exact), and the candidate bakes recorded.
  for (int n : {1, 5, 100}) {
    INFO("--max-spheres " << n);
    const CommandResult r = cli("bake " + shell_quote(kKnot) + " -o " + shell_quote(out) +
                                " --max-spheres " + std::to_string(n));
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.out, Contains("chosen for max_spheres " + std::to_string(n)));
    const nlohmann::json st = stats_of(out);
    CHECK(st["count"] == n);
    CHECK(st["nerr_kind"] == "exact");
    CHECK(st["search"]["resolutions"].size() == st["search"]["spheres"].size());
    CHECK(st["bake_seconds"].get<double>() >= st["final_bake_seconds"].get<double>());
  }
}

TEST_CASE("bake --target-error picks the smallest resolution and says which set met it",
          "[cli][bake]") {
  TempDir dir;
  const std::string out = dir.file("t.json");
  const double target = 0.08;
  CommandResult r =
      cli("bake -q " + shell_quote(kKnot) + " -o " + shell_quote(out) + " --target-error 0.08");
  REQUIRE(r.exit_code == 0);
  const nlohmann::json st = stats_of(out);
  CHECK(st["nerr_kind"] == "exact");
  CHECK(st["nerr"].get<double>() <= target);
  const int chosen = st["resolution"];
  // Smallest: the resolutions below it, baked on their own, miss the target (all four
  // of the search's window).
  for (int k = 1; k <= 4; ++k) {
    INFO("resolution " << chosen - k);
    const nlohmann::json below = bake_knot_at(chosen - k, dir.file("below.json"));
    CHECK(below["nerr_kind"] == "exact");
    CHECK(below["nerr"].get<double>() > target);
  }
  CHECK(st["search"]["errors"].size() == st["search"]["resolutions"].size());
  CHECK(st["bake_seconds"].get<double>() >= st["final_bake_seconds"].get<double>());

  // With --dilate the file holds S+, whose nerr is only a lower bound and may exceed the
  // target: the stats and the summary say the target was met by the internal set.
  r = cli("bake " + shell_quote(kKnot) + " -o " + shell_quote(out) +
          " --target-error 0.08 --dilate");
  REQUIRE(r.exit_code == 0);
  const nlohmann::json dilated = stats_of(out);
  CHECK(dilated["resolution"] == chosen);
  CHECK(dilated["nerr_internal_kind"] == "exact");
  CHECK(dilated["nerr_internal"].get<double>() == Approx(st["nerr"].get<double>()).epsilon(1e-12));
  CHECK(dilated["nerr_internal"].get<double>() <= target);
  CHECK(dilated["nerr_kind"] == "lower_bound");
  CHECK_THAT(r.out, Contains("internal S_D") && Contains("met by this internal set") &&
                        Contains("S+: union"));
}

TEST_CASE("bake --target-error no resolution meets: exit 2 naming the option and the mesh",
          "[cli][bake]") {
  // A ball's medial surface is its centre: every resolution finds about the same single
  // sphere, and doubling the resolution stops reducing the error far above 1e-6.
  TempDir dir;
  const std::string ball =
      dir.write("ball.off", medspheres::test::to_off(medspheres::make_icosphere(1.0, 3)));
  const std::string out = dir.file("ball.json");
  const CommandResult r =
      cli("bake -q " + shell_quote(ball) + " -o " + shell_quote(out) + " --target-error 1e-6");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("--target-error: for " + ball) && Contains("target error 1e-06") &&
                        Contains("the best error is") && Contains("stopped reducing"));
  CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("bake of an open mesh writes nerr null and nerr_kind undefined", "[cli][bake]") {
  TempDir dir;
  medspheres::TriangleMesh m = medspheres::make_box({1.0, 1.0, 1.0}, 2);
  m.triangles.pop_back();
  const std::string open = dir.write("open.off", medspheres::test::to_off(m));
  const std::string out = dir.file("open.json");
  const CommandResult r = cli("bake -q " + shell_quote(open) + " -o " + shell_quote(out));
  REQUIRE(r.exit_code == 0);
  const nlohmann::json st = stats_of(out);
  REQUIRE(st.contains("nerr"));
  CHECK(st["nerr"].is_null());
  CHECK(st["nerr_kind"] == "undefined");
}

TEST_CASE("bake checks its options and output path before loading the mesh", "[cli][bake]") {
  TempDir dir;
  // The mesh does not exist: an error naming the option, not the mesh, shows that the
  // option was checked first.
  const std::string missing = shell_quote(dir.file("missing.off"));
  const std::string out = " -o " + shell_quote(dir.file("o.json"));
  for (const std::string bad : {"--resolution 1", "--resolution 5000", "--object-angle 3.2",
                                "--object-angle 0", "--threads 2000", "--threads -1",
                                "--max-spheres 0", "--target-error 1", "--medial-tolerance -1"}) {
    INFO(bad);
    const CommandResult r = cli("bake -q " + missing + out + " " + bad);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(bad.substr(0, bad.find(' '))));
    CHECK_THAT(r.err, !Contains("missing.off"));
  }
  // The output path too: checked before the (missing) mesh is read.
  const std::string plain = dir.write("plain", "x");
  struct Case {
    std::string path, says;
  };
  for (const Case& c : {Case{dir.file("nodir/o.json"), "does not exist"},
                        Case{plain + "/o.json", "is not a directory"},
                        Case{dir.path().string(), "is a directory"}}) {
    INFO(c.path);
    const CommandResult r = cli("bake -q " + missing + " -o " + shell_quote(c.path));
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(c.path) && Contains(c.says));
  }
}

TEST_CASE("an output naming an input, or empty, exits 2 and the input stays", "[cli][bake]") {
  TempDir dir;
  const std::string mesh = dir.write("eight.off", medspheres::read_text_file(kEight));
  const std::string set = dir.file("eight.spheres.json");
  REQUIRE(cli("bake -q " + shell_quote(mesh) + " -o " + shell_quote(set) + " --resolution 8")
              .exit_code == 0);
  const std::string mesh_bytes = medspheres::read_text_file(mesh);
  const std::string set_bytes = medspheres::read_text_file(set);
  // The same file by another name: a symbolic link to the mesh.
  const std::string link = dir.file("link.off");
  std::filesystem::create_symlink(mesh, link);
  const std::string m = shell_quote(mesh), q = shell_quote(set);
  struct Case {
    std::string args, expect;
  };
  const std::vector<Case> cases = {
      {"bake -q " + m + " -o " + m + " --resolution 8", "--output: is the input"},
      {"bake -q " + m + " -o " + shell_quote(link) + " --resolution 8", "--output: is the input"},
      {"bake -q " + m + " --method cover --cover-start " + q + " -o " + q,
       "--output: is the input"},
      {"render " + m + " " + q + " -o " + m + " --size 32x32", "--output: is the input"},
      {"render " + m + " " + q + " -o " + q + " --size 32x32", "--output: is the input"},
      {"view " + m + " " + q + " -o " + q, "--output: is the input"},
      {"bake -q " + m + " -o ''", "--output: must not be empty"},
      {"bake -q " + m + " --method cover --cover-start ''", "--cover-start: must not be empty"},
      {"render " + m + " " + q + " -o ''", "--output: must not be empty"},
      {"view " + m + " " + q + " -o ''", "--output: must not be empty"},
      {"convert '' " + shell_quote(dir.file("o.sph")), "must not be empty"},
      {"convert " + q + " ''", "must not be empty"},
  };
  for (const Case& c : cases) {
    INFO(c.args);
    const CommandResult r = cli(c.args);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Contains(c.expect));
    CHECK(medspheres::read_text_file(mesh) == mesh_bytes);
    CHECK(medspheres::read_text_file(set) == set_bytes);
  }
  CHECK_FALSE(std::filesystem::exists(dir.file("o.sph")));
}

TEST_CASE("bake -o: links are followed, devices written in place, failures exit 1", "[cli][bake]") {
  namespace fs = std::filesystem;
  TempDir dir;
  // A symbolic link: the target is replaced by the new set, the link stays a link.
  const std::string target = dir.write("target.json", "old");
  const fs::path link = dir.path() / "link.json";
  fs::create_symlink("target.json", link);
  REQUIRE(cli("bake -q " + shell_quote(kEight) + " -o " + shell_quote(link.string()) +
              " --resolution 12")
              .exit_code == 0);
  CHECK(fs::is_symlink(fs::symlink_status(link)));
  CHECK(fs::is_regular_file(fs::symlink_status(target)));
  CHECK(medspheres::load_sphere_set(target).size() > 0);

  // /dev/null stays the character device it is (as root, renaming a temporary over it
  // would replace it with a regular file).
  struct stat before {};
  REQUIRE(::stat("/dev/null", &before) == 0);
  REQUIRE(S_ISCHR(before.st_mode));
  const CommandResult null = cli("bake " + shell_quote(kEight) + " -o /dev/null --resolution 12");
  CHECK(null.exit_code == 0);
  CHECK_THAT(null.out, Contains("-> /dev/null"));
  struct stat after {};
  REQUIRE(::stat("/dev/null", &after) == 0);
  CHECK(S_ISCHR(after.st_mode));
  CHECK(after.st_rdev == before.st_rdev);

  // A write that fails is a failure, exit 1, not bad usage: /dev/full has no space left.
  struct stat full {};
  if (::stat("/dev/full", &full) == 0 && S_ISCHR(full.st_mode)) {
    const CommandResult r = cli("bake -q " + shell_quote(kEight) + " -o /dev/full --resolution 12");
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("/dev/full") && Contains("cannot write"));
    REQUIRE(::stat("/dev/full", &full) == 0);
    CHECK(S_ISCHR(full.st_mode));
  } else {
    WARN("no /dev/full here: the exit-1 write failure is not exercised");
  }
  // Nothing else was left in the directory (no temporaries).
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    (void)e;
    ++entries;
  }
  CHECK(entries == 2);
}

TEST_CASE("bake --cover-start: given spheres become a certified cover, misuse exits 2",
          "[cli][bake]") {
  TempDir dir;
  const std::string inner = dir.file("inner.json"), yml = dir.file("start.yml");
  REQUIRE(cli("bake -q " + shell_quote(kKnot) + " -o " + shell_quote(inner) + " --max-spheres 3")
              .exit_code == 0);
  REQUIRE(
      cli("convert " + shell_quote(inner) + " " + shell_quote(yml) + " --link knot").exit_code ==
      0);
  // From a one-set file, and from a link of a per-link file: the same spheres.
  const std::string a = dir.file("a.json"), b = dir.file("b.json");
  const CommandResult r = cli("bake " + shell_quote(kKnot) + " -o " + shell_quote(a) +
                              " --method cover --cover-start " + shell_quote(inner));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("from 3 given") && Contains("certified covered"));
  REQUIRE(cli("bake -q " + shell_quote(kKnot) + " -o " + shell_quote(b) +
              " --method cover --cover-start " + shell_quote(yml) + " --cover-start-link knot")
              .exit_code == 0);
  const nlohmann::json st = stats_of(a);
  CHECK(st["certified"] == true);
  CHECK(st["count"].get<int>() <= 3);
  CHECK(nlohmann::json::parse(
            medspheres::load_sphere_set(a).metadata_json)["generator"]["params"]["mode"] ==
        "cover_tighten");
  CHECK(medspheres::load_sphere_set(a).spheres.size() ==
        medspheres::load_sphere_set(b).spheres.size());
  // Misuse: a link the file lacks, a budget beside the start, the medial method, a batch.
  const std::string out = dir.file("bad.json");
  const std::string mesh = " " + shell_quote(kKnot) + " -o " + shell_quote(out);
  for (const auto& [args, expect] : std::vector<std::pair<std::string, std::string>>{
           {" --method cover --cover-start " + shell_quote(yml) + " --cover-start-link arm",
            "--cover-start-link"},
           {" --method cover --max-spheres 4 --cover-start " + shell_quote(inner), "excludes"},
           {" --cover-start " + shell_quote(inner), "--cover-start"},
           {" " + shell_quote(kEight) + " --method cover --cover-start " + shell_quote(inner),
            "--cover-start"}}) {
    INFO(args);
    const CommandResult bad = cli("bake" + mesh + args);
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Contains(expect));
    CHECK_FALSE(std::filesystem::exists(out));
  }
}

TEST_CASE("bake's cover search flags reach the file, and misuse exits 2 naming the flag",
          "[cli][bake]") {
  TempDir dir;
  const std::string good = dir.file("good.json"), out = dir.file("c.json");
  const CommandResult r = cli("bake -q " + shell_quote(kEight) + " -o " + shell_quote(good) +
                              " --method cover --max-spheres 6 --protrusion-allowance 0 "
                              "--protrusion-restarts 2 --balance-rounds 40");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto params =
      nlohmann::json::parse(medspheres::load_sphere_set(good).metadata_json)["generator"]["params"];
  CHECK(params["protrusion_allowance"] == 0.0);
  CHECK(params["protrusion_restarts"] == 2);
  CHECK(params["balance_rounds"] == 40);
  const std::string mesh = " " + shell_quote(kEight) + " -o " + shell_quote(out);
  for (const auto& [args, expect] : std::vector<std::pair<std::string, std::string>>{
           {" --method cover --max-spheres 6 --balance-rounds -1",
            "--balance-rounds: must be >= 0, got -1"},
           {" --method cover --max-spheres 6 --protrusion-allowance -0.5",
            "--protrusion-allowance: must be finite and >= 0, got -0.5"},
           {" --max-spheres 6 --protrusion-restarts 3", "--protrusion-restarts"},
           {" --method cover --cover-start " + shell_quote(good) + " --balance-rounds 4",
            "--balance-rounds"}}) {
    INFO(args);
    const CommandResult bad = cli("bake" + mesh + args);
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Contains(expect));
    CHECK_FALSE(std::filesystem::exists(out));
  }
}
