// The robust solid (robust_solid.h) on generated shapes of known volume, and the bake
// that falls back to it.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/bake/cover_record.h"
#include "medspheres/cover/cover_input.h"
#include "medspheres/error.h"
#include "medspheres/measure/solid_choice.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/mesh/robust_solid.h"
#include "medspheres/options/bake_flags.h"
#include "support/shared_meshes.h"

using namespace medspheres;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The largest distance from the input's surface a point of the robust solid can have.
double offset(const RobustSolid& s) {
  return s.wall_radius + std::sqrt(3.0) * s.cell;
}

// Every triangle on its own three vertices, shrunk towards its centroid by \p shrink (gaps
// between neighbours), and with probability \p flip wound the other way.
TriangleMesh soup_of(const TriangleMesh& m, double shrink, double flip, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  TriangleMesh soup;
  for (std::size_t t = 0; t < m.num_triangles(); ++t) {
    const Eigen::Vector3d c = (m.corner(t, 0) + m.corner(t, 1) + m.corner(t, 2)) / 3.0;
    const int b = static_cast<int>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(c + (1.0 - shrink) * (m.corner(t, k) - c));
    if (u(rng) < flip)
      soup.triangles.push_back({b, b + 2, b + 1});
    else
      soup.triangles.push_back({b, b + 1, b + 2});
  }
  return soup;
}

// The box [-1, 1]^3 (8 x 8 quads a face) without the triangles of its top face (z = 1)
// whose centroid lies in [lo, hi]^2: a square hole.
TriangleMesh box_with_hole(double lo, double hi) {
  TriangleMesh box = make_box({1.0, 1.0, 1.0}, 8);
  TriangleMesh out;
  out.vertices = box.vertices;
  for (std::size_t t = 0; t < box.num_triangles(); ++t) {
    const Eigen::Vector3d c = (box.corner(t, 0) + box.corner(t, 1) + box.corner(t, 2)) / 3.0;
    bool top = true;
    for (int k = 0; k < 3; ++k) top = top && box.corner(t, k).z() == 1.0;
    const bool hole = top && c.x() > lo && c.x() < hi && c.y() > lo && c.y() < hi;
    if (!hole) out.triangles.push_back(box.triangles[t]);
  }
  return out;
}

// A flat square of side 2 split into 8 x 8 quads, tilted about two axes (no grid axis
// lies in its plane), so that no thickness lines up with the cells.
TriangleMesh tilted_sheet() {
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  TriangleMesh sheet;
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i)
      sheet.vertices.push_back(turn * Eigen::Vector3d(-1.0 + i / 4.0, -1.0 + j / 4.0, 0.0));
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      const int a = j * 9 + i;
      sheet.triangles.push_back({a, a + 1, a + 10});
      sheet.triangles.push_back({a, a + 10, a + 9});
    }
  return sheet;
}

// Appends the side of the cylinder of \p radius about the axis through \p base along
// \p axis (unit), of \p length, without caps: an open tube of 2 * 24 triangles.
void add_open_tube(TriangleMesh& m, const Eigen::Vector3d& base, const Eigen::Vector3d& axis,
                   double radius, double length) {
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  const int b = static_cast<int>(m.vertices.size());
  constexpr int kSlices = 24;
  for (int k = 0; k < kSlices; ++k) {
    const double a = 2.0 * kPi * k / kSlices;
    const Eigen::Vector3d rim = radius * (std::cos(a) * u + std::sin(a) * v);
    m.vertices.push_back(base + rim);
    m.vertices.push_back(base + length * axis + rim);
  }
  for (int k = 0; k < kSlices; ++k) {
    const int i = b + 2 * k, j = b + 2 * ((k + 1) % kSlices);
    m.triangles.push_back({i, j, j + 1});
    m.triangles.push_back({i, j + 1, i + 1});
  }
}

// Like the visual mesh of a robot's wrist: two open tubes (no end caps: openings as wide
// as the part) that run into each other (self-intersecting), single surfaces (walls of no
// thickness), the second wound inward, so that no winding number is confident inside.
TriangleMesh open_elbow() {
  TriangleMesh m;
  add_open_tube(m, {0.0, 0.0, -1.0}, Eigen::Vector3d::UnitZ(), 0.5, 2.0);
  const std::size_t first = m.triangles.size();
  add_open_tube(m, {-0.2, 0.0, 0.3}, Eigen::Vector3d::UnitX(), 0.4, 1.4);
  for (std::size_t t = first; t < m.triangles.size(); ++t)
    std::swap(m.triangles[t][1], m.triangles[t][2]);
  return m;
}

void check_closed_solid(const RobustSolid& s) {
  const MeshReport r = analyze_mesh(s.mesh);
  CHECK(r.closed);
  CHECK(r.inconsistent_edges == 0);
  CHECK(r.is_closed_outward());
}

// Each sphere inside the solid bounded by \p q's closed mesh: its centre inside (exact
// winding number) and its radius at most the centre's distance to the boundary.
void check_spheres_inside(const SphereSet& set, const MeshQuery& q) {
  for (const Sphere& s : set.spheres) {
    CHECK(q.winding_number_exact(s.center) > 0.5);
    CHECK(s.radius <= q.closest_point(s.center).distance());
  }
}

}  // namespace

TEST_CASE("the robust solid of a closed box holds the box and stays within the walls",
          "[robust_solid]") {
  const TriangleMesh box = make_box({1.0, 1.0, 1.0}, 3);
  for (int n : {16, 40}) {
    INFO("resolution " << n);
    const RobustSolid s = make_robust_solid(box, {n, 0.0}, "box");
    check_closed_solid(s);
    CHECK(s.cell == Approx(2.0 / n));
    const double v = analyze_mesh(s.mesh).signed_volume;
    const double d = offset(s);
    CHECK(v >= 8.0);
    CHECK(v <= std::pow(2.0 + 2.0 * d, 3));
    // Every point of the box is in the solid (corners and centre, exactly).
    const MeshQuery q(s.mesh);
    for (const auto& v3 : box.vertices) CHECK(q.winding_number_exact(v3) > 0.5);
    CHECK(q.winding_number_exact(Eigen::Vector3d::Zero()) > 0.5);
    CHECK(q.winding_number_exact(Eigen::Vector3d(1.0 + d + 1e-9, 0, 0)) < 0.5);
  }
}

TEST_CASE("the robust solid of a triangle soup of a ball has the ball's volume within the walls",
          "[robust_solid]") {
  const double r = 1.0;
  const TriangleMesh soup = soup_of(make_icosphere(r, 4), 0.02, 0.5, 7);
  const RobustSolid s = make_robust_solid(soup, {64, 0.0}, "soup");
  check_closed_solid(s);
  const double v = analyze_mesh(s.mesh).signed_volume;
  // The icosphere is inscribed in the ball of radius r and contains the ball of its
  // inradius; the solid holds the polyhedron and lies within offset() of its surface.
  const double inner = 4.0 / 3.0 * kPi * std::pow(0.99 * r, 3);
  const double outer = 4.0 / 3.0 * kPi * std::pow(r + offset(s), 3);
  CHECK(v >= inner);
  CHECK(v <= outer);
}

TEST_CASE("holes narrower than the walls are closed, wider ones leave no volume",
          "[robust_solid]") {
  // A hole of width 2 (the whole top) leaks: the flood fill fills the box.
  try {
    make_robust_solid(box_with_hole(-1.0, 1.0), {32, 0.0}, "open.obj");
    FAIL("an open box without thickness enclosed a volume");
  } catch (const InputError& e) {
    CHECK(e.kind() == ErrorKind::kNoInterior);
    CHECK(std::string(e.what()).find("open.obj") != std::string::npos);
  }
  // A hole of 0.5 x 0.5 leaks at resolution 32 without thickness (walls of 0.117), and is
  // closed by a thickness beyond its half diagonal (0.354); the closing keeps the box.
  const TriangleMesh box = box_with_hole(0.0, 0.5);
  CHECK_THROWS_AS(make_robust_solid(box, {32, 0.0}, "hole.obj"), InputError);
  const RobustSolid s = make_robust_solid(box, {32, 0.4}, "hole.obj");
  check_closed_solid(s);
  const double v = analyze_mesh(s.mesh).signed_volume;
  CHECK(v >= 8.0);
  CHECK(v <= std::pow(2.0 + 2.0 * offset(s), 3));
  const MeshQuery q(s.mesh);
  CHECK(q.winding_number_exact(Eigen::Vector3d(0.25, 0.25, 0.95)) > 0.5);
}

TEST_CASE("a flat sheet has no robust solid: a clear error", "[robust_solid]") {
  TriangleMesh sheet;
  sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  CHECK_THROWS_AS(make_robust_solid(sheet, {}, "sheet.obj"), InputError);
  BakeRequest request;
  try {
    bake_mesh(sheet, analyze_mesh(sheet), request, "sheet.obj");
    FAIL("a flat sheet was baked");
  } catch (const InputError& e) {
    CHECK(e.kind() == ErrorKind::kNoInterior);
    // The error names the file and says why, at every resolution the search tries.
    CHECK(std::string(e.what()).find("sheet.obj") != std::string::npos);
    CHECK(std::string(e.what()).find("bounds no volume") != std::string::npos);
  }
  for (const SolidKind kind : {SolidKind::kAuto, SolidKind::kRobust}) {
    request.solid = kind;
    CHECK_THROWS_AS(bake_mesh(sheet, analyze_mesh(sheet), request, "sheet.obj"), InputError);
  }
}

TEST_CASE("a sheet encloses nothing however thick its walls", "[robust_solid]") {
  const TriangleMesh sheet = tilted_sheet();
  const double longest = analyze_mesh(sheet).largest_side();
  for (int n : {32, 48})
    for (double t : {0.001, 0.02, 0.1, 0.5}) {
      INFO("resolution " << n << ", thickness " << t << " L");
      try {
        const RobustSolid s = make_robust_solid(sheet, {n, t * longest}, "sheet.obj");
        FAIL("a sheet enclosed " << s.enclosed_cells << " cells");
      } catch (const InputError& e) {
        CHECK(e.kind() == ErrorKind::kNoInterior);
      }
    }
  // Escalating, every thickness of the schedule is tried, and the error says so.
  try {
    make_robust_solid(sheet, {0, 0.0, true}, "sheet.obj");
    FAIL("an escalated sheet enclosed a volume");
  } catch (const InputError& e) {
    CHECK(e.kind() == ErrorKind::kNoInterior);
    CHECK_THAT(e.what(),
               Catch::Matchers::Contains("sheet.obj") && Catch::Matchers::Contains("up to 0.5L"));
  }
}

TEST_CASE("an open, self-intersecting elbow: its walls are thickened until they enclose a volume",
          "[robust_solid][bake_pipeline]") {
  const TriangleMesh elbow = open_elbow();
  const MeshReport report = analyze_mesh(elbow);
  REQUIRE_FALSE(report.closed);
  // Without thickness its walls enclose nothing at any resolution the search tries.
  CHECK_THROWS_AS(make_robust_solid(elbow, {}, "elbow.obj"), InputError);
  BakeRequest request;
  request.medial.resolution = 16;
  const BakeOutcome out = bake_mesh(elbow, report, request, "elbow.obj");
  CHECK(out.solid == SolidKind::kRobust);
  CHECK(out.robust_thickness_escalated);
  CHECK(out.robust_thickness > 0.0);
  const auto meta = nlohmann::json::parse(out.spheres.metadata_json);
  CHECK(meta["stats"]["robust_thickness"].get<double>() == out.robust_thickness);
  CHECK(meta["stats"]["robust_thickness_requested"].get<double>() == 0.0);
  const bool says_so = std::any_of(out.warnings.begin(), out.warnings.end(), [](const auto& w) {
    return w.find("thickened to") != std::string::npos;
  });
  CHECK(says_so);
  // The thickness is a step of the schedule, and the steps below it enclose nothing.
  const double longest = report.largest_side();
  bool on_schedule = false;
  for (double step : kRobustThicknessSteps) {
    if (std::abs(step * longest - out.robust_thickness) <= 1e-12 * longest) on_schedule = true;
    if (step * longest < out.robust_thickness)
      CHECK_THROWS_AS(make_robust_solid(elbow, {0, step * longest}, "elbow.obj"), InputError);
  }
  CHECK(on_schedule);
  // Every inner sphere lies inside the solid the file records, which eval rebuilds.
  REQUIRE(out.spheres.size() > 0);
  const SolidChoice choice = choose_solid(SolidKind::kAuto, {}, false, out.spheres.metadata_json);
  REQUIRE(choice.kind == SolidKind::kRobust);
  CHECK(choice.robust.thickness == out.robust_thickness);
  const TriangleMesh recorded = solid_mesh(elbow, choice, "elbow.obj");
  CHECK(analyze_mesh(recorded).is_closed_outward());
  check_spheres_inside(out.spheres, MeshQuery(recorded));
  // The request the CLI and Python make from their flags (no thickness given) escalates
  // the same way; a thickness the caller gives is kept: none escalates.
  for (const SolidKind kind : {SolidKind::kAuto, SolidKind::kRobust}) {
    INFO("solid " << to_string(kind));
    BakeFlags flags;
    flags.resolution = 16;
    flags.solid.solid = to_string(kind);
    const BakeOutcome o = bake_mesh(elbow, report, bake_request(flags), "elbow.obj");
    CHECK(o.solid == SolidKind::kRobust);
    CHECK(o.robust_thickness_escalated);
    CHECK(o.robust_thickness == out.robust_thickness);
    flags.solid.robust_thickness = "0";
    CHECK_THROWS_AS(bake_mesh(elbow, report, bake_request(flags), "elbow.obj"), InputError);
  }
}

TEST_CASE("robust solid options out of range name the option", "[robust_solid]") {
  const TriangleMesh box = make_box({1.0, 1.0, 1.0});
  for (const RobustSolidOptions& o :
       {RobustSolidOptions{7, 0.0}, RobustSolidOptions{1025, 0.0}, RobustSolidOptions{32, -1.0},
        RobustSolidOptions{32, std::nan("")},
        RobustSolidOptions{32, 2.5},  // walls thicker than the box is wide (L = 2)
        RobustSolidOptions{0, 5.0}}) {
    try {
      make_robust_solid(box, o, "box");
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(e.kind() == ErrorKind::kOutOfRange);
      CHECK(e.field().rfind("robust_", 0) == 0);
    }
  }
}

TEST_CASE("the robust solid does not depend on the order of triangles and vertices",
          "[robust_solid]") {
  const TriangleMesh soup = soup_of(make_torus(1.0, 0.3, 24, 12), 0.01, 0.3, 3);
  TriangleMesh shuffled = soup;
  std::mt19937 rng(11);
  std::vector<int> perm(soup.vertices.size());
  for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = static_cast<int>(i);
  std::shuffle(perm.begin(), perm.end(), rng);
  for (std::size_t i = 0; i < perm.size(); ++i)
    shuffled.vertices[static_cast<std::size_t>(perm[i])] = soup.vertices[i];
  for (auto& t : shuffled.triangles)
    for (int& v : t) v = perm[static_cast<std::size_t>(v)];
  std::shuffle(shuffled.triangles.begin(), shuffled.triangles.end(), rng);
  const RobustSolid a = make_robust_solid(soup, {48, 0.0}, "a");
  const RobustSolid b = make_robust_solid(shuffled, {48, 0.0}, "b");
  CHECK(a.mesh.vertices == b.mesh.vertices);
  CHECK(a.mesh.triangles == b.mesh.triangles);
}

TEST_CASE("auto bakes the robust solid of an ambiguous soup, with a warning, and records it",
          "[robust_solid][bake_pipeline]") {
  const TriangleMesh soup = soup_of(make_icosphere(1.0, 3), 0.02, 0.5, 5);
  BakeRequest request;
  request.medial.resolution = 20;
  const BakeOutcome out = bake_mesh(soup, analyze_mesh(soup), request, "soup.stl");
  CHECK(out.solid == SolidKind::kRobust);
  REQUIRE(out.warnings.size() == 1);
  CHECK(out.warnings[0].find("robust solid") != std::string::npos);
  const auto meta = nlohmann::json::parse(out.spheres.metadata_json);
  CHECK(meta["stats"]["solid"] == "robust");
  CHECK(meta["source"]["triangles"] == soup.num_triangles());
  REQUIRE(out.spheres.size() > 0);
  // The guarantee holds for the solid used: every sphere inside the robust solid.
  const RobustSolid s = make_robust_solid(soup, request.robust, "soup.stl");
  check_spheres_inside(out.spheres, MeshQuery(s.mesh));
  // The resolution it chose is recorded, and eval's choice rebuilds that very solid.
  CHECK(meta["stats"]["robust_resolution"].get<int>() == s.resolution);
  CHECK(meta["stats"]["robust_triangles"].get<std::size_t>() == s.mesh.num_triangles());
  const SolidChoice choice = choose_solid(SolidKind::kAuto, {}, false, out.spheres.metadata_json);
  CHECK(choice.kind == SolidKind::kRobust);
  const TriangleMesh rebuilt = solid_mesh(soup, choice, "soup.stl");
  CHECK(rebuilt.vertices == s.mesh.vertices);
  CHECK(rebuilt.triangles == s.mesh.triangles);
  // The winding-number solid, asked for explicitly, is refused.
  request.solid = SolidKind::kWinding;
  CHECK_THROWS_AS(bake_mesh(soup, analyze_mesh(soup), request, "soup.stl"), InputError);
}

TEST_CASE("auto keeps the winding-number solid of a closed mesh, robust is there on request",
          "[robust_solid][bake_pipeline]") {
  const TriangleMesh ball = make_icosphere(1.0, 3);
  BakeRequest request;
  request.medial.resolution = 20;
  const BakeOutcome w = bake_mesh(ball, analyze_mesh(ball), request, "ball");
  CHECK(w.solid == SolidKind::kWinding);
  CHECK(w.warnings.empty());
  CHECK(nlohmann::json::parse(w.spheres.metadata_json)["stats"]["solid"] == "winding");
  request.solid = SolidKind::kRobust;
  const BakeOutcome r = bake_mesh(ball, analyze_mesh(ball), request, "ball");
  CHECK(r.solid == SolidKind::kRobust);
  CHECK(r.warnings.empty());
  CHECK(nlohmann::json::parse(r.spheres.metadata_json)["stats"]["solid"] == "robust");
  // The robust solid's exact volume is recorded, and it holds the ball's polyhedron.
  REQUIRE(r.volume.has_value());
  CHECK(nlohmann::json::parse(r.spheres.metadata_json)["stats"]["mesh_volume"].get<double>() >=
        analyze_mesh(ball).signed_volume);
}

TEST_CASE("the chosen resolution keeps the boundary within the triangle budget", "[robust_solid]") {
  // A closed box: the probe at 32 is within the budget, so a finer grid is chosen.
  const TriangleMesh box = make_box({1.0, 1.0, 1.0}, 3);
  const RobustSolid s = make_robust_solid(box, {}, "box");
  check_closed_solid(s);
  CHECK(s.resolution > 32);
  CHECK(s.resolution <= 96);
  CHECK(s.mesh.num_triangles() <= kRobustTriangleBudget);
  CHECK(s.cell == Approx(2.0 / s.resolution));
  // One cell finer is over the budget (the search found the finest one).
  CHECK(make_robust_solid(box, {s.resolution + 1, 0.0}, "box").mesh.num_triangles() >
        kRobustTriangleBudget);
  // 4 x 4 x 4 separate balls: over the budget at the probe, so a coarser grid; the walls
  // of some coarser grids fill every ball (no cell enclosed), and the search passes them.
  TriangleMesh balls;
  const TriangleMesh ball = make_icosphere(0.45, 2);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) {
        const int base = static_cast<int>(balls.vertices.size());
        for (const auto& v : ball.vertices)
          balls.vertices.push_back(v + 1.5 * Eigen::Vector3d(i, j, k));
        for (const auto& t : ball.triangles)
          balls.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      }
  REQUIRE(make_robust_solid(balls, {32, 0.0}, "balls").mesh.num_triangles() >
          kRobustTriangleBudget);
  const RobustSolid coarse = make_robust_solid(balls, {}, "balls");
  check_closed_solid(coarse);
  CHECK(coarse.resolution < 32);
  CHECK(coarse.resolution >= 16);
  CHECK(coarse.mesh.num_triangles() <= kRobustTriangleBudget);
  // It holds every ball's centre and the corners of the first ball's triangles.
  const MeshQuery q(coarse.mesh);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
        CHECK(q.winding_number_exact(1.5 * Eigen::Vector3d(i, j, k)) > 0.5);
  for (const auto& v : ball.vertices) CHECK(q.winding_number_exact(v) > 0.5);
}

namespace {

// Points on the triangles of \p mesh (uniform barycentric draws) that no ball contains:
// a sampled oracle beside the certificate.
std::size_t uncovered_samples(const TriangleMesh& mesh, const std::vector<Sphere>& balls,
                              int per_triangle, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t missed = 0;
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t)
    for (int k = 0; k < per_triangle; ++k) {
      double a = u(rng), b = u(rng);
      if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
      const Eigen::Vector3d p = mesh.corner(t, 0) + a * (mesh.corner(t, 1) - mesh.corner(t, 0)) +
                                b * (mesh.corner(t, 2) - mesh.corner(t, 0));
      bool in = false;
      for (const Sphere& s : balls) in = in || (p - s.center).norm() <= s.radius;
      missed += !in;
    }
  return missed;
}

}  // namespace

TEST_CASE("a covering set of the robust solid also certifies the input's own triangles",
          "[robust_solid][cover]") {
  // A soup of a ball's triangles with, inside it, a small loose square: the cover is
  // baked on the robust solid's boundary, the input's triangles lie inside that solid.
  TriangleMesh soup = soup_of(make_icosphere(1.0, 2), 0.02, 0.5, 9);
  const int b = static_cast<int>(soup.vertices.size());
  for (const Eigen::Vector3d& v :
       {Eigen::Vector3d(-0.2, -0.2, 0.0), Eigen::Vector3d(0.2, -0.2, 0.0),
        Eigen::Vector3d(0.2, 0.2, 0.0), Eigen::Vector3d(-0.2, 0.2, 0.0)})
    soup.vertices.push_back(v);
  soup.triangles.push_back({b, b + 1, b + 2});
  soup.triangles.push_back({b, b + 2, b + 3});
  BakeRequest request;
  request.method = BakeMethod::kCover;
  request.max_spheres = 24;
  request.solid = SolidKind::kRobust;  // auto keeps the winding number's solid for a cover
  request.robust.resolution = 24;
  const BakeOutcome out = bake_mesh(soup, analyze_mesh(soup), request, "soup.stl");
  REQUIRE(out.solid == SolidKind::kRobust);
  REQUIRE(out.cover.has_value());
  const auto stats = nlohmann::json::parse(out.spheres.metadata_json)["stats"];
  CHECK(stats["solid"] == "robust");
  CHECK(stats["input_certified"] == true);
  CHECK(stats["input_certificate_triangles"].get<std::size_t>() == soup.num_triangles());
  CHECK(stats["input_uncertified_triangles"].get<std::size_t>() == 0);
  // Independently: the certificate on the input and on the robust solid's boundary, and
  // sampled points of the input's triangles.
  CHECK(certify_cover(soup, out.spheres.spheres).certified);
  const RobustSolid s = make_robust_solid(soup, request.robust, "soup.stl");
  CHECK(certify_cover(s.mesh, out.spheres.spheres).certified);
  CHECK(uncovered_samples(soup, out.spheres.spheres, 20, 3) == 0);
}

TEST_CASE("balls that miss the input's triangles are grown until certified, stats measured again",
          "[robust_solid][cover]") {
  // The solid: a box; the cover: one ball at the centre that holds only part of a triangle
  // inside the box.
  const TriangleMesh box = make_box({1.0, 1.0, 1.0}, 2);
  const FitEvaluator fit(box, 1);
  TriangleMesh input;
  input.vertices = {{-0.8, -0.8, 0.0}, {0.8, -0.8, 0.0}, {0.0, 0.8, 0.0}};
  input.triangles = {{0, 1, 2}};
  CoverResult cover;
  cover.spheres.spheres = {{Eigen::Vector3d::Zero(), 0.3}};
  cover.stats.mesh_volume = 8.0;
  REQUIRE_FALSE(certify_cover(input, cover.spheres.spheres).certified);
  CoverOptions options;
  options.threads = 1;
  const InputCoverCheck check = certify_input_cover(input, fit, cover, options);
  CHECK(check.certificate.certified);
  CHECK(check.repaired > 0);
  CHECK(certify_cover(input, cover.spheres.spheres).certified);
  CHECK(uncovered_samples(input, cover.spheres.spheres, 2000, 5) == 0);
  // The grown ball holds the farthest corner, |(-0.8, -0.8, 0)| = 0.8 sqrt 2, and not much
  // more; the union volume is that ball's, in closed form.
  const double r = cover.spheres.spheres[0].radius;
  CHECK(r >= 0.8 * std::sqrt(2.0));
  CHECK(r <= 0.8 * std::sqrt(2.0) * (1.0 + 1e-6));
  CHECK(cover.stats.union_volume == Approx(4.0 / 3.0 * kPi * r * r * r).epsilon(1e-9));
  CHECK(cover.stats.excess_volume == Approx((cover.stats.union_volume - 8.0) / 8.0));
  // Recorded, and written as a boolean.
  BakeRecord record;
  record_input_cover(check, record);
  CHECK(record.extra_stats.at("input_certified") == 1.0);
  CHECK(record.extra_stats.at("input_repaired") == static_cast<double>(check.repaired));
  const auto meta = nlohmann::json::parse(cover_metadata_json(record));
  CHECK(meta["stats"]["input_certified"] == true);
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("every awkward shared mesh with a volume bakes, inside the solid it records",
          "[robust_solid][shared]") {
  for (const auto& row : test::shared_meshes()) {
    if (row.classic()) continue;
    INFO(row.file);
    const LoadedMesh loaded = load_mesh(row.path);
    BakeRequest request;
    request.measure = false;
    BakeOutcome out;
    try {
      out = bake_mesh(loaded.mesh, loaded.report, request, row.file);
    } catch (const InputError& e) {
      // Only a mesh that bounds nothing may be refused: 100 random triangles.
      CHECK(row.category == "awkward:soup");
      CHECK(e.kind() == ErrorKind::kNoInterior);
      continue;
    }
    REQUIRE(out.spheres.size() > 0);
    const bool robust = out.solid == SolidKind::kRobust;
    CHECK(nlohmann::json::parse(out.spheres.metadata_json)["stats"]["solid"] ==
          to_string(out.solid));
    CHECK(robust == !out.warnings.empty());
    if (!robust) continue;
    const MeshQuery q(make_robust_solid(loaded.mesh, request.robust, row.file).mesh);
    check_spheres_inside(out.spheres, q);
  }
}
#endif
