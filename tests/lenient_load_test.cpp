// Loading what viewers load (a scene whose non-mesh parts fail assimp's validation),
// refusing headers that announce more than the file holds before anything is allocated,
// and the canonical order of a loaded mesh.
#include <chrono>
#include <cstdint>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh/canonical_order.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "support/mesh_writers.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::test;

namespace {

std::string write(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = (dir.path() / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// \p dae with a node that instances one camera twice: assimp names both cameras after
// the node, and its validation rejects the duplicate name.
std::string with_twin_cameras(std::string dae) {
  const std::string cameras = R"(<library_cameras><camera id="cam" name="cam"><optics>
    <technique_common><perspective><yfov>45</yfov><aspect_ratio>1</aspect_ratio>
    <znear>0.1</znear><zfar>100</zfar></perspective></technique_common></optics></camera>
  </library_cameras>
  )";
  const std::string nodes =
      R"(<node id="c" name="c"><instance_camera url="#cam"/><instance_camera url="#cam"/></node>
  </visual_scene>)";
  dae.insert(dae.find("<library_geometries>"), cameras);
  dae.replace(dae.find("</visual_scene>"), std::string("</visual_scene>").size(), nodes);
  return dae;
}

void check_fails_fast(const std::string& path, const std::string& words) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    load_mesh(path);
    FAIL("loaded " << path);
  } catch (const InputError& e) {
    INFO(e.what());
    CHECK(std::string(e.what()).find(path) != std::string::npos);
    CHECK(std::string(e.what()).find(words) != std::string::npos);
  }
  // Far below the import's timeout (30 s), which is what an allocation would meet.
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 5.0);
}

}  // namespace

TEST_CASE("a COLLADA scene that fails validation for its cameras gives its triangles",
          "[mesh_io][lenient]") {
  const TriangleMesh box = make_box({1.0, 2.0, 3.0});
  const TempDir dir;
  const std::string path =
      write(dir, "twins.dae", with_twin_cameras(to_dae(box, Eigen::Matrix4d::Identity())));
  const LoadedMesh loaded = load_mesh(path);
  CHECK(loaded.mesh.num_triangles() == box.num_triangles());
  CHECK(loaded.report.closed);
  CHECK(loaded.report.signed_volume == Approx(48.0));
  bool warned = false;
  for (const std::string& w : loaded.warnings)
    warned = warned || w.find("validation") != std::string::npos;
  CHECK(warned);
}

TEST_CASE("headers that announce 10^12 elements fail fast, naming the file", "[mesh_io][huge]") {
  const TempDir dir;
  check_fails_fast(write(dir, "big.off",
                         "OFF\n1000000000000 1000000000000 0\n0 0 0\n1 0 0\n"
                         "0 1 0\n3 0 1 2\n"),
                   "truncated");
  const std::string ply_head =
      "element vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  check_fails_fast(write(dir, "big.ply",
                         "ply\nformat ascii 1.0\n" + ply_head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                   "1000000000000 'vertex'");
  check_fails_fast(write(dir, "bigbin.ply", "ply\nformat binary_little_endian 1.0\n" + ply_head),
                   "vertex");
  // Binary STL counts triangles in 32 bits: the largest count, in a file of one triangle.
  std::string stl(80, '\0');
  const std::uint32_t count = 4000000000u;
  stl.append(reinterpret_cast<const char*>(&count), 4);
  stl.append(50, '\0');
  check_fails_fast(write(dir, "big.stl", stl), "announces 4000000000 triangles");
  check_fails_fast(write(dir, "big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1000000000000\n"),
                   "big.obj");
}

TEST_CASE("canonicalize_order forgets the order of vertices, triangles and corners",
          "[mesh_io][canonical]") {
  TriangleMesh a;
  a.vertices = {{1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  a.triangles = {{1, 2, 0}, {1, 0, 3}, {1, 3, 2}, {0, 2, 3}};
  TriangleMesh b;
  b.vertices = {{0, 0, 1}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}};   // 3, 2, 1, 0 of a
  b.triangles = {{0, 3, 1}, {1, 3, 2}, {1, 2, 0}, {0, 2, 3}};  // a's, shuffled and rotated
  canonicalize_order(a);
  canonicalize_order(b);
  CHECK(a.vertices == b.vertices);
  CHECK(a.triangles == b.triangles);
  CHECK(a.vertices.front() == Eigen::Vector3d(0, 0, 0));
  // The winding survives: the tetrahedron's signed volume keeps its sign.
  double v = 0;
  for (const auto& t : a.triangles)
    v += a.vertices[t[0]].dot(a.vertices[t[1]].cross(a.vertices[t[2]])) / 6.0;
  CHECK(v == Approx(1.0 / 6.0));
}
