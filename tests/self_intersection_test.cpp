// Self-intersecting triangle pairs: each case of the definition on two triangles, meshes
// whose pairs are known by construction, brute force over all pairs, and the manifest of
// the shared meshes.
#include "medspheres/measure/self_intersection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "support/sanitizer_build.h"
#include "support/shared_meshes.h"

using Eigen::Vector3d;
using medspheres::find_self_intersections;
using medspheres::SelfIntersections;
using medspheres::TriangleMesh;
using Pair = std::array<int, 2>;

namespace {

// The mesh of triangles t and u, given by their corners (no vertex shared by index).
TriangleMesh two(const std::array<Vector3d, 3>& t, const std::array<Vector3d, 3>& u) {
  TriangleMesh m;
  for (const Vector3d& p : t) m.vertices.push_back(p);
  for (const Vector3d& p : u) m.vertices.push_back(p);
  m.triangles = {{0, 1, 2}, {3, 4, 5}};
  return m;
}

std::size_t pairs_of(const std::array<Vector3d, 3>& t, const std::array<Vector3d, 3>& u) {
  return find_self_intersections(two(t, u)).count();
}

// \p b appended to \p a, its vertices moved by X.
TriangleMesh joined(TriangleMesh a, const TriangleMesh& b,
                    const Eigen::Isometry3d& X = Eigen::Isometry3d::Identity()) {
  const int base = static_cast<int>(a.vertices.size());
  for (const Vector3d& v : b.vertices) a.vertices.push_back(X * v);
  for (const auto& t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return a;
}

// Three fresh vertices per triangle: the same surface, nothing shared by index.
TriangleMesh unwelded(const TriangleMesh& m) {
  TriangleMesh out;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const int base = static_cast<int>(out.vertices.size());
    for (int k = 0; k < 3; ++k) out.vertices.push_back(m.corner(t, k));
    out.triangles.push_back({base, base + 1, base + 2});
  }
  return out;
}

// The number of corners two triangles share by position.
int shared_corners(const TriangleMesh& m, int t, int u) {
  int n = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      n += m.corner(static_cast<std::size_t>(t), i) == m.corner(static_cast<std::size_t>(u), j);
  return n;
}

bool all_corners(const TriangleMesh& m, int t, bool (*pred)(const Vector3d&)) {
  for (int k = 0; k < 3; ++k)
    if (!pred(m.corner(static_cast<std::size_t>(t), k))) return false;
  return true;
}

// Every pair by brute force: each pair of triangles on its own, as a two-triangle mesh over
// the same vertices. It checks that the box search misses no candidate.
std::vector<Pair> brute_force(const TriangleMesh& m) {
  std::vector<Pair> out;
  TriangleMesh pair;
  pair.vertices = m.vertices;
  const int n = static_cast<int>(m.triangles.size());
  for (int t = 0; t < n; ++t)
    for (int u = t + 1; u < n; ++u) {
      pair.triangles = {m.triangles[static_cast<std::size_t>(t)],
                        m.triangles[static_cast<std::size_t>(u)]};
      if (find_self_intersections(pair, 1).any()) out.push_back({t, u});
    }
  return out;
}

// A flat fan of n thin triangles around the origin, a disc of radius 1 (the way CAD tools
// cap a cylinder), listed \p copies times over the same vertices: every triangle's box
// holds the centre, so every pair of triangles is a candidate.
TriangleMesh fan(int n, int copies) {
  constexpr double kPi = 3.141592653589793238462643383279502884;
  TriangleMesh m;
  m.vertices.push_back(Vector3d::Zero());
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    m.vertices.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  for (int c = 0; c < copies; ++c)
    for (int k = 0; k < n; ++k) m.triangles.push_back({0, 1 + k, 1 + (k + 1) % n});
  return m;
}

// The peak resident memory of this process since the last reset_peak_memory(), in KiB
// (VmHWM); -1 where /proc/self/status does not say.
long long peak_memory_kib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stoll(line.substr(6));
  return -1;
}

// Resets the peak to the current resident memory where Linux allows it (clear_refs "5");
// elsewhere the peak stays what it was, and a growth measured from it only reads lower.
void reset_peak_memory() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

}  // namespace

TEST_CASE("two triangles: each case of the definition", "[self_intersection]") {
  const std::array<Vector3d, 3> t = {Vector3d(0, 0, 0), Vector3d(2, 0, 0), Vector3d(0, 2, 0)};
  SECTION("no shared corner: they count when they meet at all, touching included") {
    CHECK(pairs_of(t, {Vector3d(0, 0, 1), Vector3d(2, 0, 1), Vector3d(0, 2, 1)}) == 0);
    // Crossing: the vertical triangle cuts t along x = 0.5.
    CHECK(pairs_of(t, {Vector3d(0.5, 0.5, -1), Vector3d(0.5, 0.5, 1), Vector3d(0.5, -1, 0)}) == 1);
    // A vertex on t's interior, the rest above.
    CHECK(pairs_of(t, {Vector3d(0.5, 0.5, 0), Vector3d(1, 2, 1), Vector3d(2, 1, 1)}) == 1);
    // An edge lying in t, the rest above.
    CHECK(pairs_of(t, {Vector3d(0.5, 0.2, 0), Vector3d(0.2, 0.5, 0), Vector3d(0.3, 0.3, 1)}) == 1);
    // Coplanar: overlapping, disjoint, and meeting along part of an edge.
    CHECK(pairs_of(t, {Vector3d(0.5, 0.5, 0), Vector3d(3, 0.5, 0), Vector3d(0.5, 3, 0)}) == 1);
    CHECK(pairs_of(t, {Vector3d(3, 3, 0), Vector3d(4, 3, 0), Vector3d(3, 4, 0)}) == 0);
    CHECK(pairs_of(t, {Vector3d(0.5, 0, 0), Vector3d(1.5, 0, 0), Vector3d(1, -1, 0)}) == 1);
    // A near miss: a vertex 1e-300 above t. The test is exact: no contact.
    CHECK(pairs_of(t, {Vector3d(0.5, 0.5, 1e-300), Vector3d(1, 2, 1), Vector3d(2, 1, 1)}) == 0);
  }
  SECTION("one shared corner: they count when they meet anywhere else") {
    CHECK(pairs_of(t, {Vector3d(0, 0, 0), Vector3d(-1, 0, 0), Vector3d(0, -1, 1)}) == 0);
    // The edge of u opposite the shared corner pierces t.
    CHECK(pairs_of(t, {Vector3d(0, 0, 0), Vector3d(0.5, 0.5, -1), Vector3d(0.5, 0.5, 1)}) == 1);
    // Coplanar wedges that overlap, and wedges that meet along a segment beyond the corner.
    CHECK(pairs_of(t, {Vector3d(0, 0, 0), Vector3d(1, 0.2, 0), Vector3d(1, 1, 0)}) == 1);
    CHECK(pairs_of(t, {Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(1, -1, 0)}) == 1);
    // Coplanar wedges on opposite sides of the corner.
    CHECK(pairs_of(t, {Vector3d(0, 0, 0), Vector3d(-1, 0, 0), Vector3d(0, -1, 0)}) == 0);
  }
  SECTION("a shared edge: they count only when they fold onto each other") {
    CHECK(pairs_of(t, {Vector3d(0, 0, 0), Vector3d(2, 0, 0), Vector3d(0, 0, 1)}) == 0);
    CHECK(pairs_of(t, {Vector3d(0, 0, 0), Vector3d(2, 0, 0), Vector3d(0, -1, 0)}) == 0);
    CHECK(pairs_of(t, {Vector3d(2, 0, 0), Vector3d(0, 0, 0), Vector3d(0.3, 0.3, 0)}) == 1);
    CHECK(pairs_of(t, {Vector3d(0, 0, 0), Vector3d(2, 0, 0), Vector3d(5, 1e-9, 0)}) == 1);
  }
  SECTION("the same triangle twice: a pair when wound alike, not when wound oppositely") {
    CHECK(pairs_of(t, t) == 1);
    CHECK(pairs_of(t, {t[1], t[2], t[0]}) == 1);
    CHECK(pairs_of(t, {t[0], t[2], t[1]}) == 0);
    CHECK(pairs_of(t, {t[2], t[1], t[0]}) == 0);
    TriangleMesh same_indices;
    same_indices.vertices = {t[0], t[1], t[2]};
    same_indices.triangles = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}};
    CHECK(find_self_intersections(same_indices).pairs == std::vector<Pair>{{0, 2}});
  }
  SECTION("corners are compared by position: welding changes nothing, -0.0 is 0.0") {
    TriangleMesh welded;
    welded.vertices = {t[0], t[1], t[2], Vector3d(0, 0, 1)};
    welded.triangles = {{0, 1, 2}, {0, 1, 3}};  // a shared edge, not coplanar
    CHECK(find_self_intersections(welded).count() == 0);
    CHECK(find_self_intersections(unwelded(welded)).count() == 0);
    CHECK(pairs_of(t, {Vector3d(-0.0, 0, -0.0), Vector3d(2, 0, 0), Vector3d(0, 0, 1)}) == 0);
  }
}

TEST_CASE("clean closed meshes have no pairs", "[self_intersection]") {
  for (const TriangleMesh& m :
       {medspheres::make_torus(1.0, 0.3, 48, 24), medspheres::make_icosphere(1.0, 3),
        medspheres::make_box({1.0, 2.0, 3.0}, 4), medspheres::make_capsule(0.5, 1.0, 24, 8)}) {
    const SelfIntersections r = find_self_intersections(m);
    CHECK(r.count() == 0);
    CHECK_FALSE(r.any());
    CHECK(r.degenerate_triangles == 0);
    CHECK(find_self_intersections(unwelded(m)).count() == 0);
  }
}

// A: the box [-1, 1]^3. B: a cube of side 1 turned 45 degrees about the x axis, so that
// one edge (y = z = -0.5 in its own frame) points down, lowered until that edge runs at
// z = 0.9, y = 0.7, x in [-0.5, 0.5]: 0.1 below A's top face. Only the two corners of that
// edge lie below z = 1 (the next lowest vertices are at 1.607), so the triangles of B that
// cross A's top plane are the 8 incident to those corners (make_box splits each face along
// the diagonal through its (-, -) corner: both triangles of faces x = -0.5, x = +0.5,
// y = -0.5 and z = -0.5). They cross the plane inside the rectangle |x| <= 0.5,
// 0.6 <= y <= 0.8, which lies strictly inside A's top triangle on the side y > x of its
// diagonal y = x, and reaches no other face of A. So: 8 pairs, each (that triangle, one
// of the 8).
TEST_CASE("interpenetrating boxes: the 8 pairs of the construction", "[self_intersection]") {
  const TriangleMesh a = medspheres::make_box({1.0, 1.0, 1.0});
  const TriangleMesh cube = medspheres::make_box({0.5, 0.5, 0.5});
  const double c = std::sqrt(0.5);
  const Eigen::Isometry3d X = Eigen::Translation3d(0.0, 0.7, 0.9 + c) *
                              Eigen::AngleAxisd(0.25 * 3.141592653589793, Vector3d::UnitX());
  const TriangleMesh m = joined(a, cube, X);
  const int na = static_cast<int>(a.triangles.size());

  const SelfIntersections r = find_self_intersections(m);
  REQUIRE(r.count() == 8);
  CHECK(r.degenerate_triangles == 0);
  const int top = r.pairs[0][0];
  CHECK(top < na);
  CHECK(all_corners(m, top, [](const Vector3d& p) { return p.z() == 1.0; }));
  bool has_corner = false;  // A's top triangle on the side y > x holds the corner (-1, 1, 1)
  for (int k = 0; k < 3; ++k)
    has_corner |= m.corner(static_cast<std::size_t>(top), k) == Vector3d(-1, 1, 1);
  CHECK(has_corner);
  for (const Pair& p : r.pairs) {
    CHECK(p[0] == top);
    CHECK(p[1] >= na);
    CHECK_FALSE(all_corners(m, p[1], [](const Vector3d& q) { return q.z() > 1.0; }));
  }
  CHECK(std::is_sorted(r.pairs.begin(), r.pairs.end()));
  // The same with every vertex duplicated, and with the components in the other order.
  CHECK(find_self_intersections(unwelded(m)).pairs == r.pairs);
  CHECK(find_self_intersections(joined(a, cube, X)).pairs == r.pairs);
}

TEST_CASE("boxes face to face: coplanar overlap counts, and so does contact along edges",
          "[self_intersection]") {
  const TriangleMesh a = medspheres::make_box({1.0, 1.0, 1.0});
  SECTION("aligned: no pair, the touching faces are the same two triangles") {
    // B's face x = -1 lands on A's face x = 1; make_box splits both along the diagonal
    // from (y, z) = (-1, -1) to (1, 1), so each triangle of one is a triangle of the other,
    // wound oppositely; every other contact is along edges and corners the boxes share.
    const TriangleMesh m = joined(a, a, Eigen::Isometry3d(Eigen::Translation3d(2, 0, 0)));
    CHECK(find_self_intersections(m).count() == 0);
  }
  SECTION("aligned, faces split along crossing diagonals: 4 pairs") {
    // B mirrored (y -> -y) before the move: its face on x = 1 is split along the other
    // diagonal. Each triangle of A's face shares one side of the square with each triangle
    // of B's, and their third corners lie on the same side of it: 4 folds.
    Eigen::Isometry3d X(Eigen::Translation3d(2, 0, 0));
    X.linear() = Vector3d(1, -1, 1).asDiagonal();
    const TriangleMesh m = joined(a, a, X);
    const SelfIntersections r = find_self_intersections(m);
    REQUIRE(r.count() == 4);
    for (const Pair& p : r.pairs) {
      CHECK(shared_corners(m, p[0], p[1]) == 2);
      CHECK(all_corners(m, p[0], [](const Vector3d& q) { return q.x() == 1.0; }));
      CHECK(all_corners(m, p[1], [](const Vector3d& q) { return q.x() == 1.0; }));
    }
  }
  SECTION("offset: 3 coplanar overlaps, and faces meeting along segments") {
    // B moved by (2, 0.5, 0.25): its face on x = 1 spans y in [-0.5, 1.5], z in
    // [-0.75, 1.25], split along z = y - 0.25; A's along z = y. Their triangles overlap in
    // 3 of the 4 combinations (not A's z > y half with B's z < y - 0.25 half). The solids
    // lie on either side of x = 1, so every pair meets there: both triangles reach it.
    const TriangleMesh m = joined(a, a, Eigen::Isometry3d(Eigen::Translation3d(2.0, 0.5, 0.25)));
    const SelfIntersections r = find_self_intersections(m);
    std::size_t coplanar = 0;
    const auto on_plane = [](const Vector3d& q) { return q.x() == 1.0; };
    for (const Pair& p : r.pairs) {
      coplanar += all_corners(m, p[0], on_plane) && all_corners(m, p[1], on_plane);
      for (const int t : p) {
        bool reaches = false;
        for (int k = 0; k < 3; ++k) reaches |= on_plane(m.corner(static_cast<std::size_t>(t), k));
        CHECK(reaches);
      }
    }
    CHECK(coplanar == 3);
    CHECK(r.count() > 3);
    CHECK(r.pairs == brute_force(m));
  }
}

TEST_CASE("degenerate triangles are skipped and counted", "[self_intersection]") {
  // A box, a collinear triangle whose segment pierces its top face, and a collapsed one
  // (a repeated vertex) at a corner: neither is in a pair.
  TriangleMesh m = medspheres::make_box({1.0, 1.0, 1.0}, 2);
  const int base = static_cast<int>(m.vertices.size());
  m.vertices.push_back(Vector3d(0.1, 0.2, 0.5));
  m.vertices.push_back(Vector3d(0.1, 0.2, 1.0));
  m.vertices.push_back(Vector3d(0.1, 0.2, 1.5));
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({0, 0, 1});
  const SelfIntersections r = find_self_intersections(m);
  CHECK(r.degenerate_triangles == 2);
  CHECK(r.count() == 0);

  // A degenerate sliver between two proper triangles changes nothing for them.
  TriangleMesh sliver;
  sliver.vertices = {Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(2, 0, 0), Vector3d(1, 1, 0),
                     Vector3d(1, -1, 0)};
  sliver.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 4, 2}};
  const SelfIntersections s = find_self_intersections(sliver);
  CHECK(s.degenerate_triangles == 1);
  CHECK(s.count() == 0);
}

TEST_CASE("brute force over all pairs agrees, for every thread count", "[self_intersection]") {
  // Corners from a small integer lattice, so that triangles share corners, edges and
  // planes, touch and coincide; some corners repeat (collapsed triangles).
  std::mt19937 rng(12345);
  std::vector<Vector3d> pool;
  for (int i = 0; i < 40; ++i)
    pool.emplace_back(static_cast<double>(rng() % 4), static_cast<double>(rng() % 4),
                      static_cast<double>(rng() % 4));
  for (int i = 0; i < 10; ++i)  // and a few anywhere
    pool.emplace_back(static_cast<double>(rng() % 3000) / 1000.0,
                      static_cast<double>(rng() % 3000) / 1000.0,
                      static_cast<double>(rng() % 3000) / 1000.0);
  TriangleMesh m;
  m.vertices = pool;
  for (int i = 0; i < 150; ++i)
    m.triangles.push_back({static_cast<int>(rng() % pool.size()),
                           static_cast<int>(rng() % pool.size()),
                           static_cast<int>(rng() % pool.size())});
  const SelfIntersections r = find_self_intersections(m, 1);
  CHECK(r.count() > 100);
  CHECK(r.degenerate_triangles > 0);
  CHECK(r.pairs == brute_force(m));
  for (const int threads : {0, 2, 3}) CHECK(find_self_intersections(m, threads).pairs == r.pairs);
  CHECK(find_self_intersections(unwelded(m)).pairs == r.pairs);
}

TEST_CASE("a large fan: quadratic candidates in linear memory", "[self_intersection]") {
  // n triangles around one vertex: n^2 / 2 candidate pairs, 8 bytes each were they all held
  // (20000: 2e8 pairs, 1.6 GB); the peak memory may grow by an eighth of that at most. Two
  // triangles of the fan share the centre, or an edge with their third corners on either
  // side of it: none is a pair. Under a sanitizer n is 10000 (5e7 pairs, 400 MB held, in 48
  // buffers of 2^20 candidates), the same two cases of the exact test; there the growth is
  // about 26 MB for any n (the buffers and the sanitizer's own), below the 49 MB allowed.
  const int n_single = medspheres::test::kSanitizerBuild ? 10000 : 20000;
  const long long held_kib = static_cast<long long>(n_single) * (n_single - 1) / 2 * 8 / 1024;
  reset_peak_memory();
  const long long before = peak_memory_kib();
  const SelfIntersections single = find_self_intersections(fan(n_single, 1));
  const long long growth = peak_memory_kib() - before;
  CHECK(single.count() == 0);
  CHECK(single.degenerate_triangles == 0);
  INFO("peak memory grew by " << growth << " KiB; all candidates held: " << held_kib << " KiB");
  if (before >= 0) CHECK(growth < held_kib / 8);

  // A fan of 3000 listed twice: 1.8e7 candidates, tested 2^20 at a time, and the 3000
  // pairs of a triangle with its copy (the same triangle wound alike) spread over them.
  // Under a sanitizer 1500: 4.5e6 candidates, still more than 4 buffers.
  const int n = medspheres::test::kSanitizerBuild ? 1500 : 3000;
  const TriangleMesh twice = fan(n, 2);
  std::vector<Pair> expected;
  for (int k = 0; k < n; ++k) expected.push_back({k, n + k});
  const SelfIntersections r = find_self_intersections(twice, 1);
  CHECK(r.pairs == expected);
  CHECK(find_self_intersections(twice, 2).pairs == expected);
}

TEST_CASE("bad input throws std::invalid_argument", "[self_intersection]") {
  TriangleMesh m = medspheres::make_box({1.0, 1.0, 1.0});
  CHECK_THROWS_AS(find_self_intersections(m, -1), std::invalid_argument);
  TriangleMesh bad_index = m;
  bad_index.triangles[3][1] = static_cast<int>(m.vertices.size());
  CHECK_THROWS_AS(find_self_intersections(bad_index), std::invalid_argument);
  TriangleMesh nan = m;
  nan.vertices[2].y() = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(find_self_intersections(nan), std::invalid_argument);
  CHECK(find_self_intersections(TriangleMesh{}).count() == 0);
}

#ifdef MEDSPHERES_SHARED_MESHES
// The manifest's selfint_pairs is "a heuristic count" by an unknown tool. What reproduces
// it is the pairs that share no corner (by position), met with the exact test: 41 of the
// 45 meshes agree exactly. The manifest leaves out pairs that share a corner and meet
// elsewhere, which self_intersection.h counts (CGAL's convention). Four meshes differ even
// on the corner-disjoint pairs, for the reasons below (no one tolerant weld, nor a parse
// in double, matches all four); their exact counts are pinned here:
// - featuretype.STL: 1216 pairs that touch (a vertex or an edge exactly on the other
//   triangle, no crossing) across seams whose vertices are 3e-16 apart but not
//   bit-identical; any tolerant weld (1e-7 of the diagonal or more) makes them share
//   corners and the count 0, the manifest's;
// - Wuson.off (428): 494, all of them crossings or point contacts; tolerant welds give 458
//   (1e-6 of the diagonal) or 408 (1e-5), never 428;
// - cycloidal.ply (53550): 53559, of which 10232 coplanar overlaps and 13777 contacts
//   (so the manifest counts touching too); 9 more than the manifest;
// - block.obj (7): 5 (6 when the OBJ is parsed in double instead of assimp's float).
const std::map<std::string, std::size_t> kDisjointDeviations = {{"trimesh/featuretype.STL", 1216},
                                                                {"assimp/Wuson.off", 494},
                                                                {"trimesh/cycloidal.ply", 53559},
                                                                {"quartet/block.obj", 5}};

TEST_CASE("every shared mesh: corner-disjoint pairs agree with MANIFEST.tsv",
          "[self_intersection][shared]") {
  std::size_t agree = 0;
  for (const auto& row : medspheres::test::shared_meshes()) {
    INFO(row.file << ": manifest " << row.selfint_pairs);
    const medspheres::LoadedMesh loaded = medspheres::load_mesh(row.path);
    const SelfIntersections r = find_self_intersections(loaded.mesh);
    std::size_t disjoint = 0;
    for (const Pair& p : r.pairs) disjoint += shared_corners(loaded.mesh, p[0], p[1]) == 0;
    INFO("pairs " << r.count() << ", corner-disjoint " << disjoint);
    // The pairs as documented: t < u, each pair once, in increasing order.
    const int n = static_cast<int>(loaded.mesh.triangles.size());
    CHECK(std::all_of(r.pairs.begin(), r.pairs.end(),
                      [n](const Pair& p) { return 0 <= p[0] && p[0] < p[1] && p[1] < n; }));
    CHECK(std::adjacent_find(r.pairs.begin(), r.pairs.end(), [](const Pair& a, const Pair& b) {
            return !(a < b);
          }) == r.pairs.end());
    CHECK(r.degenerate_triangles == row.degenerate_triangles);
    const auto deviation = kDisjointDeviations.find(row.file);
    if (deviation == kDisjointDeviations.end()) {
      CHECK(disjoint == row.selfint_pairs);
      CHECK(r.any() == (row.selfint_pairs > 0));
      agree += disjoint == row.selfint_pairs;
    } else {
      CHECK(disjoint == deviation->second);
      CHECK(disjoint != row.selfint_pairs);
    }
  }
  CHECK(agree + kDisjointDeviations.size() == medspheres::test::shared_meshes().size());
}
#endif
