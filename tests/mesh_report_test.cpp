#include <algorithm>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_report.h"
#include "support/mesh_writers.h"
#include "support/shared_meshes.h"

using namespace medspheres;
using Catch::Matchers::Contains;
using medspheres::test::append_mesh;
using medspheres::test::cube_mesh;

TEST_CASE("a cube: counts, volume and bounding box", "[report]") {
  const MeshReport r = analyze_mesh(make_box({1, 1, 1}));
  CHECK(r.triangles == 12);
  CHECK(r.vertices == 8);
  CHECK(r.edges == 18);
  CHECK(r.components == 1);
  CHECK(r.boundary_edges == 0);
  CHECK(r.nonmanifold_edges == 0);
  CHECK(r.closed);
  CHECK(r.signed_volume == Approx(8.0));
  CHECK(r.bbox_min == Eigen::Vector3d(-1, -1, -1));
  CHECK(r.bbox_max == Eigen::Vector3d(1, 1, 1));
  REQUIRE(r.component_reports.size() == 1);
  CHECK(r.component_reports[0].orientation == Orientation::kOutward);
}

TEST_CASE("an open box has boundary edges and no orientation", "[report]") {
  TriangleMesh m = make_box({1, 1, 1});
  m.triangles.resize(10);  // drop the last face (two triangles)
  const MeshReport r = analyze_mesh(m);
  CHECK(r.boundary_edges == 4);
  CHECK_FALSE(r.closed);
  CHECK(r.component_reports[0].orientation == Orientation::kOpen);
}

TEST_CASE("three triangles on one edge make it non-manifold", "[report]") {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshReport r = analyze_mesh(m);
  CHECK(r.nonmanifold_edges == 1);
  CHECK(r.boundary_edges == 6);
  CHECK(r.components == 1);
  CHECK_FALSE(r.closed);
}

TEST_CASE("two separate boxes are two components, each closed", "[report]") {
  TriangleMesh a = make_box({1, 1, 1}), b = make_box({0.5, 0.5, 0.5});
  const int off = static_cast<int>(a.vertices.size());
  for (auto v : b.vertices) a.vertices.push_back(v + Eigen::Vector3d(5, 0, 0));
  for (auto t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
  const MeshReport r = analyze_mesh(a);
  CHECK(r.components == 2);
  CHECK(r.closed);
  CHECK(r.signed_volume == Approx(8.0 + 1.0));
}

TEST_CASE("orient_mesh turns an inward box outward and fixes a flipped triangle", "[report]") {
  TriangleMesh m = make_box({1, 2, 3}, 2);
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  CHECK(analyze_mesh(m).component_reports[0].orientation == Orientation::kInward);
  OrientationFix fix = orient_mesh(m);
  CHECK(fix.components_flipped_outward == 1);
  CHECK(fix.triangles_flipped_for_consistency == 0);
  CHECK(analyze_mesh(m).is_closed_outward());

  std::swap(m.triangles[5][1], m.triangles[5][2]);
  const MeshReport bad = analyze_mesh(m);
  CHECK(bad.inconsistent_edges == 3);
  CHECK(bad.component_reports[0].orientation == Orientation::kInconsistent);
  fix = orient_mesh(m);
  CHECK(fix.triangles_flipped_for_consistency == 1);
  CHECK(fix.components_flipped_outward == 0);
  CHECK(analyze_mesh(m).is_closed_outward());
  CHECK(analyze_mesh(m).signed_volume == Approx(48.0));
}

TEST_CASE("orient_mesh keeps cavities inward and turns the shells around them outward",
          "[report]") {
  TriangleMesh m;
  SECTION("a hollow cube is right as it is") {
    append_mesh(m, cube_mesh(0, 3), false);
    append_mesh(m, cube_mesh(1, 2), true);
    CHECK(orient_mesh(m).components_flipped_outward == 0);
    const MeshReport r = analyze_mesh(m);
    CHECK(r.signed_volume == Approx(26.0));
    CHECK(r.is_closed_outward());
    REQUIRE(r.component_reports.size() == 2);
    CHECK_FALSE(r.component_reports[0].cavity);
    CHECK(r.component_reports[1].orientation == Orientation::kInward);
    CHECK(r.component_reports[1].cavity);
  }
  SECTION("an inward cube with nothing around it is turned outward") {
    append_mesh(m, cube_mesh(1, 2), true);
    CHECK_FALSE(analyze_mesh(m).component_reports[0].cavity);
    CHECK_FALSE(analyze_mesh(m).is_closed_outward());
    CHECK(orient_mesh(m).components_flipped_outward == 1);
    CHECK(analyze_mesh(m).signed_volume == Approx(1.0));
  }
  SECTION("both shells inward: the outer one is turned, the cavity kept") {
    append_mesh(m, cube_mesh(0, 3), true);
    append_mesh(m, cube_mesh(1, 2), true);
    CHECK(orient_mesh(m).components_flipped_outward == 1);
    const MeshReport r = analyze_mesh(m);
    CHECK(r.signed_volume == Approx(26.0));
    CHECK(r.component_reports[0].orientation == Orientation::kOutward);
    CHECK(r.component_reports[1].cavity);
    CHECK(r.is_closed_outward());
  }
  SECTION("an island inside a cavity bounds material again") {
    append_mesh(m, cube_mesh(0, 5), true);
    append_mesh(m, cube_mesh(1, 4), true);
    append_mesh(m, cube_mesh(2, 3), true);
    CHECK(orient_mesh(m).components_flipped_outward == 2);
    CHECK(analyze_mesh(m).signed_volume == Approx(125.0 - 27.0 + 1.0));
  }
  SECTION("separate inward cubes are all turned") {
    append_mesh(m, cube_mesh(0, 1), true);
    append_mesh(m, cube_mesh(2, 3), true);
    CHECK(orient_mesh(m).components_flipped_outward == 2);
    CHECK(analyze_mesh(m).signed_volume == Approx(2.0));
  }
  SECTION("an outward shell inside another is left alone") {
    append_mesh(m, cube_mesh(0, 3), false);
    append_mesh(m, cube_mesh(1, 2), false);
    CHECK(orient_mesh(m).components_flipped_outward == 0);
    CHECK(analyze_mesh(m).signed_volume == Approx(28.0));
  }
}

TEST_CASE("degenerate triangles are counted", "[report]") {
  TriangleMesh m = make_box({1, 1, 1});
  m.vertices.push_back({0.5, 1.0, 1.0});  // on an edge of the top face
  m.triangles.push_back({0, 0, 1});       // repeated index
  m.triangles.push_back({0, 1, 0});       // repeated index
  const int a = 0, b = 1;
  m.vertices.push_back((m.vertices[a] + m.vertices[b]) / 2.0);  // collinear
  m.triangles.push_back({a, b, static_cast<int>(m.vertices.size() - 1)});
  CHECK(analyze_mesh(m).degenerate_triangles == 3);
}

TEST_CASE("check_mesh_usable names the problem", "[report]") {
  TriangleMesh m;
  CHECK_THROWS_WITH(check_mesh_usable(m, "a.obj"), Contains("a.obj") && Contains("no triangles"));
  m = make_box({1, 1, 1});
  m.vertices[3].x() = std::nan("");
  CHECK_THROWS_WITH(check_mesh_usable(m, "a.obj"), Contains("vertex 3") && Contains("non-finite"));
  m = make_box({1, 1, 1});
  m.vertices[2].z() = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(check_mesh_usable(m, "a.obj"), InputError);
  m = make_box({1, 1, 1});
  m.triangles[0][1] = 99;
  CHECK_THROWS_WITH(check_mesh_usable(m, "a.obj"), Contains("out of range"));
  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}, {0, 0, 1}};
  CHECK_THROWS_WITH(check_mesh_usable(flat, "a.obj"), Contains("degenerate"));
}

namespace {
bool closed_consistent_by_report(const TriangleMesh& m) {
  const MeshReport r = analyze_mesh(m);
  return r.closed && r.inconsistent_edges == 0;
}
}  // namespace

TEST_CASE("is_closed_consistent agrees with analyze_mesh", "[report]") {
  std::vector<TriangleMesh> meshes = {make_box({1, 1, 1}), make_torus(1.0, 0.3, 12, 6),
                                      make_icosphere(1.0, 2)};
  TriangleMesh open = make_box({1, 1, 1});
  open.triangles.pop_back();
  meshes.push_back(open);
  TriangleMesh flipped = make_box({1, 1, 1});
  std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
  meshes.push_back(flipped);
  TriangleMesh doubled = make_box({1, 1, 1});  // every edge used four times
  const std::size_t n = doubled.triangles.size();
  for (std::size_t t = 0; t < n; ++t) doubled.triangles.push_back(doubled.triangles[t]);
  meshes.push_back(doubled);
  TriangleMesh fin = make_box({1, 1, 1});  // a third triangle on one edge
  fin.vertices.push_back({5, 5, 5});
  fin.triangles.push_back({fin.triangles[0][0], fin.triangles[0][1], 8});
  meshes.push_back(fin);
  TriangleMesh with_collapsed = make_box({1, 1, 1});
  with_collapsed.triangles.push_back({0, 0, 1});
  meshes.push_back(with_collapsed);
  TriangleMesh two = cube_mesh(0, 1);
  append_mesh(two, cube_mesh(2, 3), true);
  meshes.push_back(two);
  int closed = 0;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    INFO("mesh " << i);
    CHECK(is_closed_consistent(meshes[i]) == closed_consistent_by_report(meshes[i]));
    closed += is_closed_consistent(meshes[i]);
  }
  CHECK(closed == 5);  // the box, torus, sphere, box with a collapsed triangle, two cubes
  CHECK_FALSE(is_closed_consistent(TriangleMesh{}));
}

#ifdef MEDSPHERES_SHARED_MESHES
TEST_CASE("is_closed_consistent agrees with analyze_mesh on every shared mesh",
          "[report][shared]") {
  MeshLoadOptions as_is;
  as_is.fix_orientation = false;
  for (const auto& row : test::shared_meshes()) {
    INFO(row.file);
    const LoadedMesh loaded = load_mesh(row.path, as_is);
    CHECK(is_closed_consistent(loaded.mesh) == closed_consistent_by_report(loaded.mesh));
  }
}

TEST_CASE("the validator agrees with MANIFEST.tsv on every shared mesh", "[report][shared]") {
  const auto& rows = test::shared_meshes();
  REQUIRE(rows.size() >= 40);
  for (const auto& row : rows) {
    INFO(row.file);
    const LoadedMesh loaded = load_mesh(row.path);
    CHECK(loaded.report.triangles == row.triangles);
    CHECK(loaded.report.closed == row.closed);
    CHECK(loaded.report.boundary_edges == row.boundary_edges);
    CHECK(loaded.report.nonmanifold_edges == row.nonmanifold_edges);
    CHECK(loaded.report.components == row.components);
    CHECK(loaded.report.degenerate_triangles == row.degenerate_triangles);
  }
}
#endif
