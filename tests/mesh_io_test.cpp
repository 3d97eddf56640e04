#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh_generators.h"
#include "medspheres/mesh_io.h"
#include "support/mesh_writers.h"
#include "support/temp_dir.h"

using namespace medspheres;
using Catch::Matchers::Contains;
using medspheres::test::TempDir;

namespace {

// The loaded mesh must be the generated one up to vertex order: same triangle count,
// same welded vertex count, closed, outward, same volume and bounds.
void check_same_solid(const LoadedMesh& got, const TriangleMesh& want, double tol) {
  const MeshReport w = analyze_mesh(want);
  CHECK(got.report.triangles == w.triangles);
  CHECK(got.report.vertices == w.vertices);
  CHECK(got.report.closed);
  CHECK(got.report.is_closed_outward());
  CHECK(got.report.signed_volume == Approx(w.signed_volume).epsilon(tol));
  CHECK((got.report.bbox_min - w.bbox_min).norm() < tol);
  CHECK((got.report.bbox_max - w.bbox_max).norm() < tol);
}

std::string error_of(const std::string& path) {
  try {
    load_mesh(path);
  } catch (const InputError& e) {
    CHECK(e.source() == path);
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("each supported format loads, welds and validates", "[mesh_io]") {
  TempDir dir;
  // assimp keeps single-precision coordinates, hence the 1e-6 relative tolerances.
  const TriangleMesh m = make_torus(1.0, 0.375, 24, 12);
  SECTION("OFF") {
    check_same_solid(load_mesh(dir.write("m.off", test::to_off(m))), m, 1e-6);
  }
  SECTION("OBJ, indexed") {
    check_same_solid(load_mesh(dir.write("m.obj", test::to_obj(m))), m, 1e-6);
  }
  SECTION("OBJ, one vertex per corner, welded back") {
    check_same_solid(load_mesh(dir.write("m.obj", test::to_obj(m, true))), m, 1e-6);
  }
  SECTION("STL, ASCII") {
    check_same_solid(load_mesh(dir.write("m.stl", test::to_stl_ascii(m))), m, 1e-6);
  }
  SECTION("STL, binary") {
    check_same_solid(load_mesh(dir.write("m.stl", test::to_stl_binary(m))), m, 1e-6);
  }
  SECTION("PLY, ASCII") {
    check_same_solid(load_mesh(dir.write("m.ply", test::to_ply_ascii(m))), m, 1e-6);
  }
  SECTION("glTF 2, embedded buffer") {
    check_same_solid(load_mesh(dir.write("m.gltf", test::to_gltf(m, {{0, 0, 0}}))), m, 1e-6);
  }
}

TEST_CASE("node transforms are applied and instanced meshes kept", "[mesh_io]") {
  TempDir dir;
  const TriangleMesh box = make_box({1, 1, 1});
  SECTION("COLLADA node matrix: scale 2 and translate") {
    Eigen::Matrix4d X = Eigen::Matrix4d::Identity();
    X.topLeftCorner<3, 3>() *= 2.0;
    X.topRightCorner<3, 1>() = Eigen::Vector3d(10, 0, -5);
    const LoadedMesh l = load_mesh(dir.write("box.dae", test::to_dae(box, X)));
    CHECK(l.report.triangles == 12);
    CHECK(l.report.closed);
    CHECK(l.report.signed_volume == Approx(64.0));
    CHECK((l.report.bbox_min - Eigen::Vector3d(8, -2, -7)).norm() < 1e-5);
    CHECK((l.report.bbox_max - Eigen::Vector3d(12, 2, -3)).norm() < 1e-5);
  }
  SECTION("glTF: one mesh placed by two nodes gives two components") {
    const LoadedMesh l =
        load_mesh(dir.write("two.gltf", test::to_gltf(box, {{0, 0, 0}, {5, 0, 0}})));
    CHECK(l.report.triangles == 24);
    CHECK(l.report.components == 2);
    CHECK(l.report.closed);
    CHECK(l.report.signed_volume == Approx(16.0));
    CHECK(l.report.bbox_max.x() == Approx(6.0));
  }
}

TEST_CASE("inward-wound meshes are flipped with a warning", "[mesh_io]") {
  TempDir dir;
  TriangleMesh m = make_icosphere(1.0, 2);
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  const LoadedMesh l = load_mesh(dir.write("in.off", test::to_off(m)));
  CHECK(l.orientation_fix.components_flipped_outward == 1);
  CHECK(l.report.is_closed_outward());
  REQUIRE_FALSE(l.warnings.empty());
  CHECK_THAT(l.warnings[0], Contains("inward"));
  MeshLoadOptions keep;
  keep.fix_orientation = false;
  CHECK(load_mesh(dir.file("in.off"), keep).report.signed_volume < 0);
}

TEST_CASE("bad mesh files get an error naming the file and the problem", "[mesh_io]") {
  TempDir dir;
  CHECK_THAT(error_of(dir.file("missing.stl")), Contains("no such file"));
  CHECK_THAT(error_of(dir.path().string()), Contains("directory"));
  CHECK_THAT(error_of(dir.write("empty.stl", "")), Contains("empty"));
  CHECK_THAT(error_of(dir.write("m.xyz", "1 2 3\n")), Contains("unsupported mesh format"));
  CHECK_THAT(error_of(dir.write("m.txt", "hello")), Contains("unsupported mesh format"));
  CHECK_THAT(error_of(dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n")),
             Contains("cannot parse") || Contains("no triangles"));
  CHECK_THAT(error_of(dir.write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")),
             Contains("non-finite") || Contains("cannot parse"));
  CHECK_THAT(error_of(dir.write("inf.off", "OFF\n3 1 0\n0 0 0\ninf 0 0\n0 1 0\n3 0 1 2\n")),
             Contains("non-finite") || Contains("cannot parse"));
  CHECK_THAT(error_of(dir.write("flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n")),
             Contains("degenerate"));
  CHECK_THAT(error_of(dir.write("garbage.stl", std::string(200, '\x07'))),
             Contains("cannot parse") || Contains("no triangles"));
  CHECK_THAT(error_of(dir.write("bad.off", "OFF\n3 1 0\n0 0 0\n")),
             Contains("cannot parse") || Contains("no triangles"));
}

TEST_CASE("file_sha256 matches known digests", "[mesh_io]") {
  CHECK(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(sha256_hex(std::string(1000000, 'a')) ==
        "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  TempDir dir;
  CHECK(file_sha256(dir.write("abc", "abc")) == sha256_hex("abc"));
  CHECK_THROWS_AS(file_sha256(dir.file("nope")), InputError);
}
