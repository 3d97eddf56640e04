// The library bake pipeline (bake_pipeline.h): the same spheres and provenance as the
// CLI's bake for the same options, and every kind of input error with its field and file.
#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/cover/cover.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/sha256.h"
#include "support/cover_solids.h"
#include "support/mesh_writers.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::test;

namespace {

// The metadata without its wall-clock fields, which differ between two runs.
nlohmann::json without_timings(const std::string& metadata) {
  nlohmann::json j = nlohmann::json::parse(metadata);
  std::function<void(nlohmann::json&)> strip = [&](nlohmann::json& node) {
    if (!node.is_object()) return;
    for (auto it = node.begin(); it != node.end();) {
      if (it.key().find("seconds") != std::string::npos) {
        it = node.erase(it);
      } else {
        strip(*it);
        ++it;
      }
    }
  };
  strip(j);
  return j;
}

// The InputError \p f throws; fails the test if it throws nothing or something else.
InputError error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  FAIL("no InputError was thrown");
  throw std::logic_error("unreachable");
}

struct CliCase {
  std::string flags;
  std::function<void(BakeRequest&)> set;
};

}  // namespace

TEST_CASE("bake_mesh gives the CLI's spheres and metadata for the same options",
          "[bake_pipeline]") {
  TempDir dir;
  const std::string torus = dir.write("torus.off", to_off(make_torus(1.0, 0.35, 40, 20)));
  const std::string capsule = dir.write("capsule.off", to_off(make_capsule(0.4, 0.6, 24, 8)));
  const std::vector<CliCase> cases = {
      {"--resolution 16", [](BakeRequest& r) { r.medial.resolution = 16; }},
      {"--resolution 12 --object-angle 0.8",
       [](BakeRequest& r) {
         r.medial.resolution = 12;
         r.medial.object_angle = 0.8;
       }},
      {"--max-spheres 40", [](BakeRequest& r) { r.max_spheres = 40; }},
      {"--target-error 0.3", [](BakeRequest& r) { r.target_error = 0.3; }},
      {"--resolution 12 --dilate --vertex-tolerance 0.01L --max-protrusion 0.02",
       [](BakeRequest& r) {
         r.medial.resolution = 12;
         r.dilate = true;
         r.vertex_tolerance = Length{0.01, true};
         r.max_protrusion = Length{0.02, false};
       }},
      {"--resolution 12 --cover 0.01L --seed 7",
       [](BakeRequest& r) {
         r.medial.resolution = 12;
         r.cover = Length{0.01, true};
         r.seed = 7;
       }},
  };
  for (const std::string& mesh : {torus, capsule}) {
    const LoadedMesh loaded = load_mesh(mesh);
    for (const CliCase& c : cases) {
      INFO(mesh << " " << c.flags);
      const std::string out = dir.file("out.json");
      const CommandResult r =
          run_cli("bake -q " + shell_quote(mesh) + " -o " + shell_quote(out) + " " + c.flags);
      REQUIRE(r.exit_code == 0);
      const SphereSet cli = load_sphere_set(out);

      BakeRequest request;
      c.set(request);
      const BakeOutcome lib =
          bake_mesh(loaded.mesh, loaded.report, request, mesh, file_sha256(mesh));
      REQUIRE(lib.spheres.size() == cli.size());
      for (std::size_t i = 0; i < cli.size(); ++i) {
        CHECK(lib.spheres.spheres[i].center == cli.spheres[i].center);
        CHECK(lib.spheres.spheres[i].radius == cli.spheres[i].radius);
      }
      CHECK(without_timings(lib.spheres.metadata_json) == without_timings(cli.metadata_json));
      // The outcome's parts agree with what was written.
      CHECK(lib.record.stats.spheres == lib.medial.spheres.size());
      REQUIRE(lib.volume);
      CHECK(lib.volume->union_measures.volume > 0.0);
      CHECK(lib.internal.has_value() == (request.dilate || request.cover.has_value()));
      // bake_file on the file is bake_mesh on the loaded mesh.
      const BakeOutcome from_file = bake_file(mesh, request);
      CHECK(without_timings(from_file.spheres.metadata_json) ==
            without_timings(lib.spheres.metadata_json));
    }
  }
}

TEST_CASE("bake_mesh without measuring writes no volume statistics", "[bake_pipeline]") {
  const TriangleMesh m = make_capsule(0.4, 0.6, 24, 8);
  BakeRequest request;
  request.medial.resolution = 12;
  const BakeOutcome measured = bake_mesh(m, analyze_mesh(m), request, "capsule");
  request.measure = false;
  const BakeOutcome bare = bake_mesh(m, analyze_mesh(m), request, "capsule");
  CHECK_FALSE(bare.volume);
  CHECK(bare.spheres.spheres.size() == measured.spheres.spheres.size());
  CHECK(nlohmann::json::parse(measured.spheres.metadata_json)["stats"].contains("nerr"));
  CHECK_FALSE(nlohmann::json::parse(bare.spheres.metadata_json)["stats"].contains("nerr"));
  CHECK(nlohmann::json::parse(bare.spheres.metadata_json)["source"]["mesh"] == "capsule");
}

TEST_CASE("every request problem is out of range or a conflict, named by its field",
          "[bake_pipeline]") {
  struct Case {
    std::function<void(BakeRequest&)> set;
    ErrorKind kind;
    std::string field, value;
  };
  const std::vector<Case> cases = {
      {[](BakeRequest& r) { r.medial.resolution = 1; }, ErrorKind::kOutOfRange, "resolution", "1"},
      {[](BakeRequest& r) { r.medial.object_angle = 4.0; }, ErrorKind::kOutOfRange, "object_angle",
       "4"},
      {[](BakeRequest& r) { r.medial.medial_tolerance = -1.0; }, ErrorKind::kOutOfRange,
       "medial_tolerance", "-1"},
      {[](BakeRequest& r) { r.medial.threads = -1; }, ErrorKind::kOutOfRange, "threads", "-1"},
      // Refused whether or not the bake would build the robust solid (a closed box does not).
      {[](BakeRequest& r) { r.robust.resolution = 5; }, ErrorKind::kOutOfRange, "robust_resolution",
       "5"},
      {[](BakeRequest& r) { r.max_spheres = 0; }, ErrorKind::kOutOfRange, "max_spheres", "0"},
      {[](BakeRequest& r) { r.target_error = 1.5; }, ErrorKind::kOutOfRange, "target_error", "1.5"},
      {[](BakeRequest& r) {
         r.max_spheres = 10;
         r.target_error = 0.1;
       },
       ErrorKind::kConflict, "max_spheres", "10"},
      {[](BakeRequest& r) {
         r.vertex_tolerance = Length{0.01, false};
       },
       ErrorKind::kConflict, "vertex_tolerance", "0.01"},
      {[](BakeRequest& r) {
         r.max_protrusion = Length{0.002, true};
       },
       ErrorKind::kConflict, "max_protrusion", "0.002L"},
      {[](BakeRequest& r) {
         r.dilate = true;
         r.vertex_tolerance = Length{0.0, true};
       },
       ErrorKind::kOutOfRange, "vertex_tolerance", "0L"},
      {[](BakeRequest& r) {
         r.dilate = true;
         r.max_protrusion = Length{-1.0, false};
       },
       ErrorKind::kOutOfRange, "max_protrusion", "-1"},
      {[](BakeRequest& r) {
         r.cover = Length{0.0, false};
       },
       ErrorKind::kOutOfRange, "cover", "0"},
      {[](BakeRequest& r) {
         r.cover_start = {{Eigen::Vector3d::Zero(), 1.0}};
       },
       ErrorKind::kConflict, "cover_start", "1 sphere"},
      {[](BakeRequest& r) {
         r.method = BakeMethod::kCover;
         r.max_spheres = 4;
         r.cover_start = {{Eigen::Vector3d::Zero(), 1.0}};
       },
       ErrorKind::kConflict, "max_spheres", "4"},
      {[](BakeRequest& r) {
         r.method = BakeMethod::kCover;
         r.cover_start = {{Eigen::Vector3d::Zero(), 1.0}, {Eigen::Vector3d::Zero(), -2.0}};
       },
       ErrorKind::kOutOfRange, "cover_start", "2 spheres"},
      {[](BakeRequest& r) { r.method = BakeMethod::kCover; }, ErrorKind::kConflict, "method",
       "cover"},
      {[](BakeRequest& r) { r.cover_search.protrusion_allowance = -0.5; }, ErrorKind::kOutOfRange,
       "protrusion_allowance", "-0.5"},
      {[](BakeRequest& r) { r.cover_search.protrusion_restarts = -2; }, ErrorKind::kOutOfRange,
       "protrusion_restarts", "-2"},
      {[](BakeRequest& r) { r.cover_search.balance_rounds = -1; }, ErrorKind::kOutOfRange,
       "balance_rounds", "-1"},
  };
  const TriangleMesh m = make_box({1, 1, 1});
  for (const Case& c : cases) {
    BakeRequest request;
    c.set(request);
    INFO(c.field);
    for (const InputError& e : {error_of([&] { validate(request); }),
                                error_of([&] { bake_mesh(m, analyze_mesh(m), request, "box"); }),
                                error_of([&] { bake_file("never-read.off", request); })}) {
      CHECK(e.kind() == c.kind);
      CHECK(e.field() == c.field);
      CHECK(e.value() == c.value);
      CHECK(e.file().empty());  // found before any mesh is read
    }
  }
  // A conflict names the fields on its other side.
  BakeRequest lone;
  lone.vertex_tolerance = Length{0.01, false};
  CHECK(error_of([&] { validate(lone); }).related() == std::vector<std::string>{"dilate", "cover"});
  // A valid request passes.
  BakeRequest fine;
  fine.cover = Length{0.003, true};
  fine.max_protrusion = Length{0.0, false};
  CHECK_NOTHROW(validate(fine));
}

TEST_CASE("problems of the mesh and of the request against it name the file", "[bake_pipeline]") {
  TempDir dir;
  const std::string missing = dir.file("missing.off");
  InputError e = error_of([&] { bake_file(missing, {}); });
  CHECK(e.kind() == ErrorKind::kFileMissing);
  CHECK(e.file() == missing);
  CHECK(e.field().empty());

  e = error_of([&] { bake_file(dir.path().string(), {}); });
  CHECK(e.kind() == ErrorKind::kFileUnreadable);
  CHECK(e.file() == dir.path().string());

  const std::string garbage = dir.write("garbage.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  e = error_of([&] { bake_file(garbage, {}); });
  CHECK(e.kind() == ErrorKind::kMalformedFile);
  CHECK(e.file() == garbage);

  const std::string unknown = dir.write("mesh.xyz", "1 2 3\n");
  e = error_of([&] { bake_file(unknown, {}); });
  CHECK(e.kind() == ErrorKind::kUnsupported);
  CHECK(e.file() == unknown);

  // A flat sheet bounds no volume.
  TriangleMesh sheet;
  sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  e = error_of([&] { bake_mesh(sheet, analyze_mesh(sheet), {}, "sheet"); });
  CHECK(e.kind() == ErrorKind::kNoInterior);
  CHECK(e.file() == "sheet");

  // An error target needs a volume: an open box has none.
  TriangleMesh open = make_box({1, 1, 1}, 2);
  open.triangles.pop_back();
  BakeRequest target;
  target.target_error = 0.3;
  e = error_of([&] { bake_mesh(open, analyze_mesh(open), target, "open box"); });
  CHECK(e.kind() == ErrorKind::kUnsupported);
  CHECK(e.field() == "target_error");
  CHECK(e.file() == "open box");

  // An explicit medial tolerance at least a cell of the finest resolution baked.
  const TriangleMesh box = make_box({1, 1, 1});
  BakeRequest coarse;
  coarse.medial.medial_tolerance = 0.5;  // L = 2, cell 2 / 28
  e = error_of([&] { bake_mesh(box, analyze_mesh(box), coarse, "box"); });
  CHECK(e.kind() == ErrorKind::kOutOfRange);
  CHECK(e.field() == "medial_tolerance");
  CHECK(e.file() == "box");
  CHECK_THAT(e.what(), Catch::Matchers::StartsWith("medial_tolerance: for box, "));

  // The output path: a write that cannot happen.
  e = error_of([&] { check_output_path(dir.file("nodir/out.json")); });
  CHECK(e.kind() == ErrorKind::kWriteFailed);
}

#ifdef MEDSPHERES_SOURCE_DIR
TEST_CASE("a budget gives exactly that many inner spheres, or a cover within it",
          "[bake_pipeline]") {
  const std::string knot = example_mesh("knot1.off");
  BakeRequest one;
  one.max_spheres = 1;
  const BakeOutcome inner = bake_file(knot, one);
  CHECK(inner.spheres.size() == 1);
  REQUIRE(inner.volume);
  CHECK(inner.volume->kind == NerrKind::kExact);
  BakeRequest cover = one;
  cover.method = BakeMethod::kCover;
  cover.max_spheres = 6;
  const BakeOutcome c = bake_file(knot, cover);
  REQUIRE(c.cover);
  CHECK(c.spheres.size() <= 6);
  CHECK(c.cover->certificate.certified);
  CHECK(nlohmann::json::parse(c.spheres.metadata_json)["generator"]["method"] == "cover");
  // A cover needs a budget, and takes no error target or dilation.
  cover.max_spheres.reset();
  CHECK(error_of([&] { validate(cover); }).kind() == ErrorKind::kConflict);
  cover.max_spheres = 6;
  cover.dilate = true;
  CHECK(error_of([&] { validate(cover); }).field() == "dilate");
  // Or the cover starts from given spheres (the inner one, which misses most of the knot):
  // a certified cover of at most as many, recorded as tightened.
  BakeRequest start;
  start.method = BakeMethod::kCover;
  start.cover_start = {inner.spheres.spheres.front(), inner.spheres.spheres.front()};
  start.cover_start[1].center.x() += 0.1 * start.cover_start[1].radius;
  const BakeOutcome t = bake_file(knot, start);
  REQUIRE(t.cover);
  CHECK(t.cover->certificate.certified);
  CHECK(t.spheres.size() <= 2);
  CHECK(nlohmann::json::parse(t.spheres.metadata_json)["generator"]["params"]["mode"] ==
        "cover_tighten");
}

TEST_CASE("a cover's search settings reach the bake and its file", "[bake_pipeline]") {
  const TriangleMesh knot = load_mesh(example_mesh("knot1.off")).mesh;
  BakeRequest request;
  request.method = BakeMethod::kCover;
  request.max_spheres = 6;
  request.medial.threads = 1;
  request.cover_search = {0.0, 2, 40};
  const BakeOutcome out = bake_mesh(knot, analyze_mesh(knot), request, "knot");
  // The same balls as bake_cover with those options, bit for bit, and not the default's.
  CoverOptions options;
  options.threads = 1;
  options.protrusion_allowance = 0.0;
  options.protrusion_restarts = 2;
  options.balance_rounds = 40;
  const MeshQuery query(knot);
  test::check_same_spheres(out.spheres.spheres, bake_cover(query, 6, options).spheres.spheres);
  const std::vector<Sphere> plain = bake_cover(query, 6,
                                               [] {
                                                 CoverOptions o;
                                                 o.threads = 1;
                                                 return o;
                                               }())
                                        .spheres.spheres;
  CHECK(!test::same_spheres(out.spheres.spheres, plain));
  const auto params = nlohmann::json::parse(out.spheres.metadata_json)["generator"]["params"];
  CHECK(params["protrusion_allowance"] == 0.0);
  CHECK(params["protrusion_restarts"] == 2);
  CHECK(params["balance_rounds"] == 40);
}
#endif

TEST_CASE("bake_mesh on a shared FitEvaluator gives the same spheres as on the mesh",
          "[bake_pipeline]") {
  const TriangleMesh m = make_torus(1.0, 0.35, 32, 16);
  const MeshReport report = analyze_mesh(m);
  const FitEvaluator fit(m, 1);
  for (const BakeMethod method : {BakeMethod::kMedial, BakeMethod::kCover}) {
    BakeRequest r;
    r.method = method;
    r.max_spheres = 6;
    r.medial.threads = 1;
    const BakeOutcome own = bake_mesh(m, report, r, "torus");
    const BakeOutcome shared = bake_mesh(fit, report, r, "torus");
    REQUIRE(own.spheres.size() == shared.spheres.size());
    for (std::size_t i = 0; i < own.spheres.size(); ++i) {
      CHECK(own.spheres.spheres[i].center == shared.spheres.spheres[i].center);
      CHECK(own.spheres.spheres[i].radius == shared.spheres.spheres[i].radius);
    }
  }
  BakeRequest bad;
  bad.max_spheres = 0;
  CHECK_THROWS_AS(bake_mesh(fit, report, bad, "torus"), InputError);
}
