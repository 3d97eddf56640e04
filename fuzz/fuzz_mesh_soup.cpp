// The mesh front end on arbitrary triangle soups: the bytes become the scene an import
// would give (scene_import.h: placed meshes of vertices and triangles), and go through
// what load_mesh does after assimp (welding, check_mesh_usable, orient_mesh,
// analyze_mesh), then into MeshQuery. Oracles:
// - orientation is idempotent: orienting the loaded mesh again flips nothing;
// - welding merges exactly the bit-identical finite points: no two vertices are equal;
// - closest_point agrees with brute force over every triangle (holes' caps included).
#include <cmath>
#include <limits>
#include <unordered_set>

#include <fuzzer/FuzzedDataProvider.h>

#include "../src/mesh/scene_import.h"
#include "fuzz_support.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/point_triangle.h"

namespace {

using medspheres::detail::FlatMesh;
using medspheres::detail::FlatScene;

// Coordinates from a small palette (so that points coincide, edges are shared and
// triangles are degenerate often) or any double.
double coordinate(FuzzedDataProvider& in) {
  static const double kPalette[] = {0.0,
                                    -0.0,
                                    1.0,
                                    -1.0,
                                    0.5,
                                    2.0,
                                    1e-300,
                                    1e300,
                                    3.0,
                                    1e-9,
                                    1e9,
                                    std::numeric_limits<double>::denorm_min(),
                                    std::numeric_limits<double>::quiet_NaN(),
                                    std::numeric_limits<double>::infinity()};
  const std::uint8_t pick = in.ConsumeIntegral<std::uint8_t>();
  if (pick < 224) return kPalette[pick % 8];
  if (pick < 240) return kPalette[pick % (sizeof kPalette / sizeof kPalette[0])];
  return in.ConsumeFloatingPoint<double>();
}

FlatScene scene_of(FuzzedDataProvider& in) {
  FlatScene scene;
  const int meshes = in.ConsumeIntegralInRange(1, 3);
  for (int m = 0; m < meshes && in.remaining_bytes() > 0; ++m) {
    FlatMesh mesh;
    const std::size_t nv = in.ConsumeIntegralInRange<std::size_t>(1, 48);
    for (std::size_t k = 0; k < 3 * nv; ++k) mesh.xyz.push_back(coordinate(in));
    const std::size_t nt = in.ConsumeIntegralInRange<std::size_t>(0, 64);
    for (std::size_t k = 0; k < 3 * nt; ++k)
      mesh.index.push_back(in.ConsumeIntegral<std::uint32_t>() % static_cast<std::uint32_t>(nv));
    scene.meshes.push_back(std::move(mesh));
  }
  return scene;
}

double brute_force_distance(const medspheres::TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t)
    best = std::min(best, (p - medspheres::closest_point_on_triangle(
                                   p, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)))
                              .stableNorm());
  return best;
}

void check_queries(const medspheres::TriangleMesh& mesh, bool cap_holes, FuzzedDataProvider& in) {
  medspheres::MeshQueryOptions options;
  options.cap_holes = cap_holes;
  const medspheres::MeshQuery query(mesh, options);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d p(coordinate(in), coordinate(in), coordinate(in));
    if (!p.allFinite()) continue;
    const double d = query.closest_point(p).distance();
    const double brute =
        std::min(brute_force_distance(query.mesh(), p), brute_force_distance(query.cap_mesh(), p));
    // The accuracy MeshQuery states (point_triangle.h's kernel bound, with the scale its
    // own tests use): within 32 u S, S = |p| + d + 2 |diagonal of the mesh's bounds|.
    // Relative to the whole mesh: one vertex at 1e300 leaves no precision for a query
    // near a feature of size 1 (their squares share no exponent range).
    const double scale = p.stableNorm() + brute + 2 * query.mesh().bounds().sizes().stableNorm();
    if (std::isfinite(brute) && std::isfinite(scale) &&
        !(std::abs(d - brute) <= 32 * 0x1p-53 * scale)) {
      std::fprintf(stderr, "p = (%.17g, %.17g, %.17g): closest_point %.17g, brute force %.17g\n",
                   p.x(), p.y(), p.z(), d, brute);
      for (const Eigen::Vector3d& v : mesh.vertices)
        std::fprintf(stderr, "v %.17g %.17g %.17g\n", v.x(), v.y(), v.z());
      for (const auto& t : mesh.triangles) std::fprintf(stderr, "f %d %d %d\n", t[0], t[1], t[2]);
      MEDSPHERES_FUZZ_CHECK(!"closest_point agrees with brute force");
    }
    (void)query.winding_number(p);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres;
  FuzzedDataProvider in(data, size);
  const bool orient = in.ConsumeBool();
  const bool cap_holes = in.ConsumeBool();
  const FlatScene scene = scene_of(in);
  LoadedMesh loaded;
  if (!fuzz::accepts([&] { loaded = detail::mesh_from_scene(scene, "fuzz.stl", orient); }))
    return 0;
  const TriangleMesh& mesh = loaded.mesh;

  std::unordered_set<std::string> seen;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    if (!v.allFinite()) continue;
    const Eigen::Vector3d w = v + Eigen::Vector3d::Zero();  // -0.0 + 0.0 == +0.0
    MEDSPHERES_FUZZ_CHECK(
        seen.insert(std::string(reinterpret_cast<const char*>(w.data()), sizeof(double) * 3))
            .second);
  }
  if (orient) {
    TriangleMesh again = mesh;
    const OrientationFix fix = orient_mesh(again);
    MEDSPHERES_FUZZ_CHECK(fix.triangles_flipped_for_consistency == 0);
    MEDSPHERES_FUZZ_CHECK(fix.components_flipped_outward == 0);
  }
  (void)boundary_loops(mesh);
  check_queries(mesh, cap_holes, in);
  return 0;
}
