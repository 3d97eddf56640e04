// Properties of a bake under changes of the input that do not change the solid: a
// permutation of the file's vertices and triangles (bit-identical output), a uniform scale
// (millimetres against metres), a rigid motion (within stated tolerances).
#include <cmath>
#include <fstream>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/mesh/mesh_report.h"
#include "support/mesh_writers.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::test;

namespace {

// The bundled knot, the mesh every property is checked on.
TriangleMesh knot() {
  return load_mesh(example_mesh("knot1.off")).mesh;
}

BakeOutcome bake_of(const TriangleMesh& m) {
  BakeRequest request;
  request.medial.threads = 2;
  return bake_mesh(m, analyze_mesh(m), request, "mesh");
}

TriangleMesh transformed(TriangleMesh m, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                         double scale) {
  for (auto& v : m.vertices) v = scale * (R * v) + t;
  return m;
}

std::string write(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = (dir.path() / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

}  // namespace

TEST_CASE("a file that lists the same mesh in another order loads and bakes bit-identically",
          "[properties]") {
  const TriangleMesh m = knot();
  std::mt19937 rng(2024);
  std::vector<int> perm(m.vertices.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), rng);
  TriangleMesh p;
  p.vertices.resize(m.vertices.size());
  for (std::size_t i = 0; i < perm.size(); ++i)
    p.vertices[static_cast<std::size_t>(perm[i])] = m.vertices[i];
  for (auto t : m.triangles) {
    for (int& v : t) v = perm[static_cast<std::size_t>(v)];
    std::rotate(t.begin(), t.begin() + static_cast<long>(rng() % 3), t.end());  // same winding
    p.triangles.push_back(t);
  }
  std::shuffle(p.triangles.begin(), p.triangles.end(), rng);
  const TempDir dir;
  const LoadedMesh a = load_mesh(write(dir, "a.off", to_off(m)));
  const LoadedMesh b = load_mesh(write(dir, "b.off", to_off(p)));
  CHECK(a.mesh.vertices == b.mesh.vertices);
  CHECK(a.mesh.triangles == b.mesh.triangles);
  const BakeOutcome ba = bake_of(a.mesh), bb = bake_of(b.mesh);
  REQUIRE(ba.spheres.size() == bb.spheres.size());
  for (std::size_t i = 0; i < ba.spheres.size(); ++i) {
    CHECK(ba.spheres.spheres[i].center == bb.spheres.spheres[i].center);
    CHECK(ba.spheres.spheres[i].radius == bb.spheres.spheres[i].radius);
  }
}

TEST_CASE("a bake scales with its mesh: exactly by a power of two, within 1e-3 of nerr by 1000",
          "[properties]") {
  const TriangleMesh m = knot();
  const BakeOutcome base = bake_of(m);
  REQUIRE(base.spheres.size() > 0);
  // By 1024 every operation of the bake scales exactly, so the spheres do.
  const BakeOutcome exact =
      bake_of(transformed(m, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 1024.0));
  REQUIRE(exact.spheres.size() == base.spheres.size());
  for (std::size_t i = 0; i < exact.spheres.size(); ++i) {
    CHECK(exact.spheres.spheres[i].center == 1024.0 * base.spheres.spheres[i].center);
    CHECK(exact.spheres.spheres[i].radius == 1024.0 * base.spheres.spheres[i].radius);
  }
  // Millimetres against metres: the coordinates round differently, a few cells keep
  // another candidate, and the fit stays within 1e-3 of nerr (measured: 6e-5).
  for (double scale : {1000.0, 0.001}) {
    INFO("scale " << scale);
    const BakeOutcome s =
        bake_of(transformed(m, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), scale));
    CHECK(std::abs(static_cast<double>(s.spheres.size()) -
                   static_cast<double>(base.spheres.size())) <= 0.02 * base.spheres.size());
    CHECK(s.volume->nerr == Approx(base.volume->nerr).margin(1e-3));
  }
}

TEST_CASE("a bake moved with its mesh fits as well, within 0.03 of nerr", "[properties]") {
  const TriangleMesh m = knot();
  const double base = bake_of(m).volume->nerr;
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
    const Eigen::Vector3d t(10.0 * g(rng), 10.0 * g(rng), 10.0 * g(rng));
    const TriangleMesh moved = transformed(m, R, t, 1.0);
    const BakeOutcome out = bake_of(moved);
    INFO("trial " << trial << " nerr " << out.volume->nerr << " against " << base);
    // The grid follows the mesh's axis-aligned box, so spheres differ; the fit does not.
    CHECK(std::abs(out.volume->nerr - base) <= 0.03);
    // The guarantee is the same in every pose: every sphere inside the moved solid.
    const MeshQuery query(moved);
    for (const Sphere& s : out.spheres.spheres) {
      CHECK(query.winding_number_exact(s.center) > 0.5);
      CHECK(s.radius <= query.closest_point(s.center).distance());
    }
  }
}
