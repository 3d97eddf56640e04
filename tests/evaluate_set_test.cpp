// eval's library calls (evaluate_set.h, evaluate_set_robot.h, solid_choice.h; the options
// layer's solid_request): the solid chosen, figures against closed forms, robot rows from a
// file and from a map.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/measure/evaluate_set.h"
#include "medspheres/measure/solid_choice.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/mesh/robust_solid.h"
#include "medspheres/options/bake_flags.h"
#include "medspheres/robot/package_path.h"
#include "medspheres/robot_bake/evaluate_set_robot.h"
#include "support/temp_dir.h"
#include "support/urdf_fixtures.h"

using namespace medspheres;
using medspheres::test::TempDir;

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

// What a robust bake records (bake_pipeline.cpp), at resolution \p n and thickness \p t.
std::string robust_metadata(int n, double t) {
  nlohmann::json j;
  j["stats"] = {{"solid", "robust"}, {"robust_resolution", n}, {"robust_thickness", t}};
  return j.dump();
}

SolidFlags flags(const std::string& solid, int resolution = RobustSolidOptions{}.resolution,
                 std::optional<std::string> thickness = std::nullopt) {
  return {solid, resolution, std::move(thickness)};
}

// The field of the InputError \p f throws; "" when it throws none.
template <class F>
std::string error_field(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.field();
  }
  return "";
}

double ball_volume(double r) {
  return 4.0 / 3.0 * kPi * r * r * r;
}

FitOptions fast_fit() {
  FitOptions o;
  o.volume_samples = 20000;
  o.surface_samples = 2000;
  return o;
}

}  // namespace

TEST_CASE("eval's solid: the recorded one under auto, the named one otherwise", "[eval]") {
  const std::string robust32 = robust_metadata(32, 0.002);
  SolidChoice c = eval_solid(solid_request(flags("auto")), 2.0, robust32);
  CHECK(c.kind == SolidKind::kRobust);
  CHECK(c.robust.resolution == 32);
  CHECK(c.robust.thickness == 0.002);
  CHECK(eval_solid(solid_request(flags("winding")), 2.0, robust32).kind == SolidKind::kWinding);
  // robust without options of its own takes the recorded ones, or the defaults
  c = eval_solid(solid_request(flags("robust")), 2.0, robust32);
  CHECK((c.kind == SolidKind::kRobust && c.robust.resolution == 32 && c.robust.thickness == 0.002));
  c = eval_solid(solid_request(flags("robust")), 2.0, "");
  CHECK((c.kind == SolidKind::kRobust && c.robust.resolution == RobustSolidOptions{}.resolution &&
         c.robust.thickness == 0.0));
  // options given are the user's, all of them; a thickness in L is of the mesh's L
  c = eval_solid(solid_request(flags("robust", 48)), 2.0, robust32);
  CHECK((c.robust.resolution == 48 && c.robust.thickness == 0.0));
  c = eval_solid(solid_request(flags("robust", RobustSolidOptions{}.resolution, "0.01L")), 2.0,
                 robust32);
  CHECK((c.robust.resolution == RobustSolidOptions{}.resolution && c.robust.thickness == 0.02));
  c = eval_solid(solid_request(flags("robust", 20, "0.5")), 2.0, "");
  CHECK((c.robust.resolution == 20 && c.robust.thickness == 0.5));
  // files of other tools, winding bakes and text that is no JSON name no robust solid
  for (const std::string& meta :
       {std::string(), std::string("not json"), std::string(R"({"generator": {"name": "foam"}})"),
        std::string(R"({"stats": {"solid": "winding"}})"), std::string(R"({"stats": 3})")})
    CHECK(eval_solid(solid_request(flags("auto")), 2.0, meta).kind == SolidKind::kWinding);
  // nonsense names its option, from the options layer (solid_request) as from the library
  // (eval_solid)
  CHECK(error_field([] { solid_request(flags("robst")); }) == "solid");
  CHECK(error_field([] { solid_request(flags("robust", 96, "-1")); }) == "robust_thickness");
  CHECK(error_field([] { solid_request(flags("auto", 96, "thin")); }) == "robust_thickness");
  CHECK(error_field([&] {
          eval_solid(solid_request(flags("robust", 96, "nan")), 2.0, robust32);
        }) == "robust_thickness");
  CHECK(error_field([] { solid_request(flags("robust", 24, "0.01L")); }).empty());
  // the library checks a typed request itself, whoever made it
  SolidRequest nan_thickness{SolidKind::kRobust, {}, Length{std::nan(""), false}};
  CHECK(error_field([&] { eval_solid(nan_thickness, 2.0, robust32); }) == "robust_thickness");
  CHECK(error_field([&] { check_solid_request(nan_thickness); }) == "robust_thickness");
  SolidRequest coarse{SolidKind::kAuto, {5, 0.0}, std::nullopt};
  CHECK(error_field([&] { check_solid_request(coarse); }) == "robust_resolution");
  CHECK(error_field([&] { eval_solid(coarse, 2.0, ""); }) == "robust_resolution");
  SolidRequest negative{SolidKind::kAuto, {}, Length{-0.5, true}};
  CHECK(error_field([&] { eval_solid(negative, 2.0, ""); }) == "robust_thickness");
}

TEST_CASE("eval of a mesh measures the solid it chose: one ball in a box, closed forms", "[eval]") {
  // The box [-1, 1]^3 (volume 8) and one ball inside it.
  const LoadedMesh box = prepare_mesh(make_box({1.0, 1.0, 1.0}, 4), "box");
  SphereSet set;
  set.spheres.push_back({Eigen::Vector3d(0.1, -0.2, 0.3), 0.5});
  const double ball = ball_volume(0.5);

  const MeshEvaluation w = evaluate_mesh_set(box, "box.off", set, "ball.json", fast_fit());
  CHECK(w.solid.kind == SolidKind::kWinding);
  CHECK(w.longest == 2.0);
  REQUIRE(w.evaluation.fit.volume.mesh_volume);
  CHECK(*w.evaluation.fit.volume.mesh_volume == Approx(8.0).epsilon(1e-12));
  CHECK(w.evaluation.fit.volume.kind == NerrKind::kExact);
  CHECK(w.evaluation.fit.volume.nerr == Approx(1.0 - ball / 8.0).epsilon(1e-9));
  // the ball's nearest face is 0.7 from its centre: it stays 0.2 inside
  CHECK(w.evaluation.fit.volume.max_protrusion == Approx(-0.2).epsilon(1e-9));
  nlohmann::json j = nlohmann::json::parse(evaluation_json(w));
  CHECK(j["solid"] == "winding");
  CHECK_FALSE(j.contains("robust_resolution"));
  CHECK(j["mesh"] == "box.off");
  CHECK(j["spheres_file"] == "ball.json");
  CHECK(j["bbox_largest_side"] == 2.0);

  // The same set as a robust bake records it: measured against that robust solid, which
  // holds the box and lies within its offset (robust_solid.h).
  set.metadata_json = robust_metadata(16, 0.0);
  const MeshEvaluation r = evaluate_mesh_set(box, "box.off", set, "ball.json", fast_fit());
  CHECK(r.solid.kind == SolidKind::kRobust);
  CHECK(r.solid.robust.resolution == 16);
  const RobustSolid at16 = make_robust_solid(box.mesh, {16, 0.0}, "box");
  const double v16 = analyze_mesh(at16.mesh).signed_volume;
  const double reach = 1.0 + at16.wall_radius + std::sqrt(3.0) * at16.cell;
  REQUIRE(r.evaluation.fit.volume.mesh_volume);
  const double v = *r.evaluation.fit.volume.mesh_volume;
  CHECK(v > 8.0);
  CHECK(v <= 8.0 * reach * reach * reach);
  CHECK(v == Approx(v16).epsilon(1e-12));
  // not the default resolution's solid
  const double v96 = analyze_mesh(make_robust_solid(box.mesh, {}, "box").mesh).signed_volume;
  CHECK(std::abs(v - v96) > 1e-6 * v96);
  CHECK(r.evaluation.fit.volume.nerr == Approx(1.0 - ball / v).epsilon(1e-9));
  CHECK(std::any_of(r.warnings.begin(), r.warnings.end(), [](const std::string& line) {
    return line == "box.off: measured against its robust solid at resolution 16 (solid robust)";
  }));
  j = nlohmann::json::parse(evaluation_json(r));
  CHECK(j["solid"] == "robust");
  CHECK(j["robust_resolution"] == 16);
  CHECK(j["robust_thickness"] == 0.0);
  CHECK(j["mesh_volume"].get<double>() == v);

  // --solid winding overrides what the file records
  const MeshEvaluation back = evaluate_mesh_set(box, "box.off", set, "ball.json", fast_fit(),
                                                solid_request(flags("winding")));
  CHECK(*back.evaluation.fit.volume.mesh_volume == Approx(8.0).epsilon(1e-12));
  // a bad option is reported, named
  CHECK(error_field([&] {
          evaluate_mesh_set(box, "box.off", set, "ball.json", fast_fit(),
                            solid_request(flags("robust", 3)));
        }) == "robust_resolution");
}

TEST_CASE("eval of a robot: rows in the URDF's order, from a file as from a map", "[eval][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  UrdfReadOptions read;
  add_package_dir(read.packages, "arm_pkg=" + (dir.path() / "pkg/arm_pkg").string());
  // The hand: the box hand.obj (half extents 0.02, 0.03, 0.04), a ball inside it and its
  // sphere primitive (radius 0.015 at z = 0.06).
  std::map<std::string, SphereSet> spheres;
  spheres["hand"].spheres = {{Eigen::Vector3d(0.0, 0.0, 0.0), 0.01},
                             {Eigen::Vector3d(0.0, 0.0, 0.06), 0.015}};
  const RobotEvaluation e = evaluate_robot_spheres(urdf, read, spheres, "hand.yml", fast_fit());
  REQUIRE(e.links.size() == 4);
  CHECK(e.links[0].link == "base");
  CHECK(e.links[1].link == "forearm");
  CHECK(e.links[3].link == "tool");
  const LinkFit& hand = e.links[2];
  CHECK(hand.spheres == 2);
  CHECK(hand.primitives == 1);
  REQUIRE(hand.fit);
  // the box's corners as the OBJ loader (assimp) reads them: in single precision
  const auto side = [](double half) { return 2.0 * static_cast<double>(static_cast<float>(half)); };
  const double box = side(0.02) * side(0.03) * side(0.04);
  CHECK(hand.fit->volume.kind == NerrKind::kExact);
  CHECK(hand.fit->volume.nerr == Approx(1.0 - ball_volume(0.01) / box).epsilon(1e-9));
  CHECK_FALSE(e.links[1].fit);
  CHECK(e.links[3].note == "no collision geometry");

  // The same spheres in a cuRobo file: the same rows, bit for bit but for the clocks.
  formats::SphereDocument doc;
  doc.links.push_back({"hand", spheres["hand"].spheres});
  const std::string yml = dir.write(
      "arm.curobo.yml", formats::sphere_document_text(doc, formats::SphereFormat::kCurobo));
  const RobotEvaluation f = evaluate_robot_file(urdf, read, yml, fast_fit());
  REQUIRE(f.links[2].fit);
  CHECK(f.links[2].fit->volume.nerr == hand.fit->volume.nerr);
  CHECK(f.links[2].fit->monte_carlo.error.estimate == hand.fit->monte_carlo.error.estimate);
  CHECK(f.links[2].fit->coverage.max == hand.fit->coverage.max);
  const nlohmann::json j = nlohmann::json::parse(robot_evaluation_json(f));
  CHECK(j["urdf"] == urdf);
  CHECK(j["spheres_file"] == yml);
  REQUIRE(j["links"].size() == 4);
  CHECK(j["links"][2]["nerr"].get<double>() == hand.fit->volume.nerr);
  CHECK(j["links"][2]["primitives"] == 1);
  CHECK_FALSE(j["links"][1].contains("nerr"));

  // A file of one set is not a robot's.
  SphereSet one;
  one.spheres = spheres["hand"].spheres;
  const std::string single = dir.file("one.json");
  save_sphere_set(one, single);
  try {
    read_robot_spheres(single);
    FAIL("a one-set file was read as a robot's");
  } catch (const InputError& err) {
    CHECK(err.file() == single);
    CHECK(std::string(err.what()).find("not a robot's") != std::string::npos);
  }
  // A link the robot lacks is listed, not measured; the rows are those without it.
  spheres["elbow"] = one;
  const RobotEvaluation g = evaluate_robot_spheres(urdf, read, spheres, "mine", fast_fit());
  CHECK(g.unknown_links == std::vector<std::string>{"elbow"});
  REQUIRE(g.links.size() == 4);
  REQUIRE(g.links[2].fit);
  CHECK(g.links[2].fit->volume.nerr == hand.fit->volume.nerr);
  CHECK(nlohmann::json::parse(robot_evaluation_json(g))["unknown_links"][0] == "elbow");
  // A file none of whose links the robot has is not this robot's: an error naming it.
  try {
    evaluate_robot_spheres(urdf, read, {{"elbow", one}}, "mine", fast_fit());
    FAIL("a file of another robot was measured");
  } catch (const InputError& err) {
    CHECK(err.file() == "mine");
    CHECK(std::string(err.what()).find("'elbow'") != std::string::npos);
  }
}

TEST_CASE("eval of a robot: each measured link's surface certificate", "[eval][robot]") {
  TempDir dir;
  const std::string urdf = medspheres::test::write_arm(dir);
  UrdfReadOptions read;
  add_package_dir(read.packages, "arm_pkg=" + (dir.path() / "pkg/arm_pkg").string());
  // The hand's box (half extents 0.02, 0.03, 0.04; half diagonal 0.0539) and its sphere
  // primitive: a ball of radius 0.01 inside the box leaves its surface uncovered, one of
  // radius 0.06 about its centre holds it whole.
  const Sphere primitive{Eigen::Vector3d(0.0, 0.0, 0.06), 0.015};
  for (const double radius : {0.01, 0.06}) {
    INFO("radius " << radius);
    std::map<std::string, SphereSet> spheres;
    spheres["hand"].spheres = {{Eigen::Vector3d::Zero(), radius}, primitive};
    const RobotEvaluation e = evaluate_robot_spheres(urdf, read, spheres, "hand.yml", fast_fit());
    const LinkFit& hand = e.links[2];
    REQUIRE(hand.certificate);
    CHECK(hand.certificate->certified == (radius > 0.054));
    CHECK_FALSE(e.links[1].certificate);  // no spheres, no fit, no certificate
    const nlohmann::json j = nlohmann::json::parse(robot_evaluation_json(e));
    const nlohmann::json& c = j["links"][2]["surface_certificate"];
    CHECK(c["certified"] == hand.certificate->certified);
    CHECK(c.contains("worst_uncovered_distance") == !hand.certificate->certified);
    // the corners at z = -0.04 are 0.0539 - 0.01 = 0.0439 from the small ball, farther from
    // the primitive
    if (!hand.certificate->certified)
      CHECK(c["worst_uncovered_distance"].get<double>() == Approx(0.0439).margin(1e-3));
  }
}
