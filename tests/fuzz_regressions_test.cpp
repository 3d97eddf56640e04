// Inputs the fuzzers of fuzz/ found, each reduced to what triggered the failure, and the
// committed fuzz inputs themselves (fuzz/corpus/*/crash-*): readers answer with an
// InputError naming the file, never with another exception, and the mesh query's
// hierarchy builds on any finite coordinates.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/formats/curobo_yaml.h"
#include "medspheres/formats/sph_file.h"
#include "medspheres/formats/spherized_urdf.h"
#include "medspheres/formats/xrdf.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/point_triangle.h"
#include "support/ball_formulas.h"

using namespace medspheres;

namespace {

std::string corpus_file(const std::string& name) {
  std::ifstream in(std::string(MEDSPHERES_SOURCE_DIR) + "/fuzz/corpus/" + name, std::ios::binary);
  REQUIRE(in);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The message of the InputError that read(text) throws; fails on any other outcome.
template <class Read>
std::string input_error_of(Read read, const std::string& text) {
  try {
    read(text, "in.yml");
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("no InputError");
  return {};
}

}  // namespace

TEST_CASE("cuRobo YAML whose keys hold scalars where mappings belong is an input error",
          "[fuzz][formats]") {
  // yaml-cpp throws its own BadSubscript for a key looked up in a scalar.
  for (const std::string& text :
       {std::string("robot_cfg: 3\n"), std::string("robot_cfg:\n  kinematics: 1\n"),
        std::string("kinematics: x\n"), std::string("collision_spheres: {a: 1}\n"),
        corpus_file("fuzz_curobo_yaml/crash-scalar-robot-cfg.yml")}) {
    INFO(text);
    const std::string message = input_error_of(formats::parse_curobo_yaml, text);
    CHECK_THAT(message, Catch::StartsWith("in.yml: "));
  }
  CHECK_THAT(input_error_of(formats::parse_curobo_yaml, "robot_cfg: 3\n"),
             Catch::Contains("unexpected YAML structure (line 1)"));
}

TEST_CASE("XRDF whose keys hold scalars or mappings where others belong is an input error",
          "[fuzz][formats]") {
  const std::string head =
      "format: xrdf\ngeometry:\n  g:\n    spheres:\n      a:\n"
      "        - {center: [0, 0, 0], radius: 1}\n";
  for (const std::string& text :
       {head + "collision: 3\n", head + "collision:\n  geometry: {x: 1}\n",
        std::string("format: xrdf\ngeometry:\n  g: 3\n"),
        std::string("format: xrdf\ngeometry:\n  [a]: {spheres: {}}\n"),
        corpus_file("fuzz_xrdf/crash-scalar-collision.xrdf")}) {
    INFO(text);
    CHECK_THAT(input_error_of(formats::parse_xrdf, text), Catch::StartsWith("in.yml: "));
  }
  // The well-formed file still reads.
  CHECK(formats::parse_xrdf(head, "in.xrdf").size() == 1);
}

TEST_CASE(".sph headers with counts beyond any integer type are an input error",
          "[fuzz][formats]") {
  // The counts were converted to long before their range was checked (undefined behaviour,
  // which the sanitizer build reports).
  for (const std::string& text :
       {std::string("8294726277218876156038 1\n0 0 0 1 1\n"), std::string("1 1e300\n0 0 0 1 1\n"),
        std::string("nan 1\n0 0 0 1 1\n"), std::string("2.5 1\n0 0 0 1 1\n"),
        corpus_file("fuzz_sph/crash-huge-level-count.sph")}) {
    INFO(text);
    CHECK_THAT(input_error_of(formats::parse_sph_levels, text),
               Catch::Contains("the first line is not \"levels degree\""));
  }
  CHECK(formats::parse_sph_levels("1 1\n0 0 0 1 1\n", "in.sph").size() == 1);
}

TEST_CASE("MeshQuery builds over centroids spread across the whole double range",
          "[fuzz][mesh_query]") {
  // Centroids from -1e307 to 1e307: the binning's 16 (c - lo) overflowed to infinity and
  // was converted to int (undefined behaviour, which the sanitizer build reports).
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    const double x = -1e307 + i * (2e307 / 7);
    const int v = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back({x, 0, 0});
    mesh.vertices.push_back({x, 1, 0});
    mesh.vertices.push_back({x, 0, 1});
    mesh.triangles.push_back({v, v + 1, v + 2});
  }
  const MeshQuery query(mesh);
  // Brute force over every triangle; the accuracy is the kernel's, relative to the
  // mesh's size (mesh_query.h).
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(-1e307, 2, 2), Eigen::Vector3d(0.9e307, -1, 0)}) {
    double brute = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t)
      brute = std::min(brute, (p - closest_point_on_triangle(p, mesh.corner(t, 0),
                                                             mesh.corner(t, 1), mesh.corner(t, 2)))
                                  .stableNorm());
    const double scale = p.stableNorm() + brute + 2 * mesh.bounds().sizes().stableNorm();
    REQUIRE(std::isfinite(scale));
    CHECK(std::abs(query.closest_point(p).distance() - brute) <= 32 * 0x1p-53 * scale);
  }
}

TEST_CASE("MeshQuery caps a hole whose vertices lie near the largest double",
          "[fuzz][mesh_query]") {
  // The centre of the cap's fan was the sum of the hole's vertices over their count: the
  // sum overflowed, and the cap's non-finite vertex made the constructor throw.
  TriangleMesh mesh;
  mesh.vertices = {{1.5e308, 0, 0}, {1.5e308, 1e308, 0}, {1.5e308, 0, 1e308}};
  mesh.triangles = {{0, 1, 2}};
  MeshQueryOptions options;
  options.cap_holes = true;
  const MeshQuery query(mesh, options);
  REQUIRE(query.cap_mesh().num_triangles() == 3);
  for (const Eigen::Vector3d& v : query.cap_mesh().vertices) CHECK(v.allFinite());
  // The fan's centre is the mean of the three corners.
  CHECK(query.cap_mesh().vertices.back().isApprox(Eigen::Vector3d(1.5e308, 1e308 / 3, 1e308 / 3)));
}

TEST_CASE("MeshQuery answers on a mesh whose extent is subnormal", "[fuzz][mesh_query]") {
  // The box scale was 2^1074, infinite: a query's box coordinates became NaN, every slot
  // of a node passed the box test, the empty ones too, and the walk read node INT32_MIN.
  const double tiny = std::numeric_limits<double>::denorm_min();
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {tiny, 0, 0}, {0, tiny, 0}};
  mesh.triangles = {{0, 1, 2}};
  const MeshQuery query(mesh);
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(-2, 0, 0.5)}) {
    const ClosestPoint c = query.closest_point(p);
    CHECK(c.triangle == 0);
    CHECK(c.distance() == Approx(p.norm()).margin(1e-300));
  }
}

TEST_CASE("a URDF that tinyxml2 reads but does not write back well-formed is refused",
          "[fuzz][formats]") {
  // Stray content after a self-closed root and a control character: read, but printed as
  // text that is not well-formed XML.
  const std::string text = corpus_file("fuzz_spherized_urdf/crash-not-written-back.urdf");
  const formats::RobotSpheres spheres = formats::parse_urdf_spheres(text, "in.urdf");
  try {
    (void)formats::spherize_urdf(text, spheres, "in.urdf");
    FAIL("no InputError");
  } catch (const InputError& e) {
    CHECK_THAT(std::string(e.what()), Catch::StartsWith("in.urdf (as written back): "));
  }
}

TEST_CASE("spherizing a URDF that defines a link twice is refused", "[fuzz][formats]") {
  const std::string text = R"(<robot name="r">
  <link name="upper"/>
  <link name="upper"><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
</robot>)";
  formats::RobotSpheres spheres(1);
  spheres[0].link = "upper";
  spheres[0].spheres.push_back({{0, 0, 0}, 0.1});
  try {
    (void)formats::spherize_urdf(text, spheres, "in.urdf");
    FAIL("no InputError");
  } catch (const InputError& e) {
    CHECK_THAT(std::string(e.what()), Catch::Contains("\"upper\" is defined twice"));
  }
}

TEST_CASE("the union of two nearly coincident balls of one radius keeps its precision",
          "[fuzz][union_volume]") {
  // fuzz_union_volume (crash-near-coincident-pair): two balls of radius 5.8e-3 whose
  // centres are 1.5e-11 apart. The lens height was computed from (d - r0) + r1, rounded
  // at the scale of r, and came out eps r^2 / d off: the union of the eight balls of that
  // input was 3e-14 below its exact value (no three of them overlap, so
  // inclusion-exclusion stops at the pairs), smaller than without one of the two.
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const double r = 0.0057764705882352944;
  const Sphere a{{-0.054122070339939238, 0.0011256613696294712, 0.044318385043404213}, r};
  const Sphere b{{-0.054122070327906717, 0.0011256613730924042, 0.044318385034662955}, r};
  const double one = test::ball_volume(r);
  const double d = (a.center - b.center).norm();
  const double pair = 2 * one - test::lens_volume(r, r, d);
  CHECK(measure_union({a, b}).volume >= one);
  CHECK(std::abs(measure_union({a, b}).volume - pair) <= 64 * kEps * one);
  // The same at every separation from 1e-15 r to r, along a diagonal.
  for (int k = 1; k <= 15; ++k) {
    const double s = r * std::pow(10.0, -k);
    INFO("d = " << s);
    const Sphere c{a.center + s * Eigen::Vector3d(1, 1, 1).normalized(), r};
    const double sd = (c.center - a.center).norm();
    const double closed = 2 * one - test::lens_volume(r, r, sd);
    CHECK(std::abs(measure_union({a, c}).volume - closed) <= 64 * kEps * one);
  }
}

TEST_CASE("a ball and three copies of a small far ball: the union is the two balls",
          "[fuzz][union_volume]") {
  // fuzz_union_volume (crash-far-duplicates-few-hits): the library was right; the fuzzer's
  // Monte Carlo check took its sigma from the estimate, and 3 hits where 14 were expected
  // looked like 6 sigma. The check now uses Bernstein's bound around the expected count.
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const Sphere a{{-0.046874999999999514, 0.00063203463570138396, -0.29999999998474919},
                 0.0070208959729552633};
  const Sphere b{Eigen::Vector3d::Constant(-0.30000000000000004), 0.005000000000000001};
  const UnionMeasures m = measure_union({a, b, b, b});
  const double exact = test::ball_volume(a.radius) + test::ball_volume(b.radius);
  CHECK(std::abs(m.volume - exact) <= 64 * kEps * exact);
  CHECK(m.duplicates == std::vector<int>{2, 3});
}

TEST_CASE("a needle tetrahedron (three tiny balls on a large sphere) keeps its volume",
          "[fuzz][union_volume]") {
  // fuzz_union_volume (crash-needle-tetrahedron): a ball of radius 1.8e8 with three balls of
  // radius 7.4e-5 on its sphere, 4e8 from the origin. The four-ball term took six times the
  // centre tetrahedron's volume (3e-27 after rescaling) from the far centre, where rounding
  // leaves 3e-18: the dihedral angles came out near pi / 2 and the union 12% below the
  // large ball alone. The tiny balls add at most 3 * 1.7e-12 to a volume of 2.4e25.
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const std::vector<Sphere> balls = {
      {{-298942738.59936219, -300000000, 298031598.3843137}, 178530377.44829518},
      {{-418595660.10096854, -393691708.77384079, 204339881.80809242}, 7.4231617189947669e-05},
      {{-418595660.10096514, -393691708.77388382, 204339881.80803201}, 7.4231499801786263e-05},
      {{-418595660.10093123, -393691708.77394933, 204339881.80804032}, 7.4231499801784447e-05}};
  const UnionMeasures m = measure_union(balls);
  REQUIRE(m.tetrahedra == 1);
  const double large = test::ball_volume(balls[0].radius);
  CHECK(std::abs(m.volume - large) <= 64 * kEps * large);
  // The same shape at every scale of the small balls from 1e-3 to 1e-12 of the large one,
  // centred near the origin: a needle whatever the coordinates' magnitude.
  for (int k = 3; k <= 12; ++k) {
    const double r = std::pow(10.0, -k);
    INFO("small radius " << r);
    const Eigen::Vector3d c(0.3, -0.2, 0.1), on = c + Eigen::Vector3d(1, 2, 2) / 3.0;
    const std::vector<Sphere> needle = {{c, 1.0},
                                        {on + Eigen::Vector3d(r, 0, 0) / 2, r},
                                        {on + Eigen::Vector3d(0, r, -r) / 2, r},
                                        {on + Eigen::Vector3d(-r, -r, r / 2) / 2, r}};
    const UnionMeasures n = measure_union(needle);
    REQUIRE(n.tetrahedra == 1);
    const double one = test::ball_volume(1.0);
    CHECK(n.volume >= one - 64 * kEps * one);
    CHECK(n.volume <= one + 3 * test::ball_volume(r) + 64 * kEps * one);
  }
}
