// Self-intersecting triangle pairs; see self_intersection.h for the definitions.
#include "medspheres/measure/self_intersection.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include <CGAL/Bbox_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include "medspheres/threads.h"

namespace medspheres {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;
// One box per non-degenerate triangle, carrying its index; CGAL identifies a box by its
// address, which stays fixed because the boxes live in one vector that is not resized.
using Box =
    CGAL::Box_intersection_d::Box_with_info_d<double, 3, int,
                                              CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

// CGAL's cutoff between the streamed segment tree and brute force, as in its
// Polygon_mesh_processing::self_intersections.
constexpr std::ptrdiff_t kBoxCutoff = 2000;

// Candidate pairs tested at a time: 8 MiB of pairs (and 1 MiB of flags), enough for the
// parallel tests to outweigh a fork and join of the threads by far.
constexpr std::size_t kCandidateBuffer = std::size_t{1} << 20;

void check_mesh(const TriangleMesh& mesh) {
  if (mesh.triangles.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("find_self_intersections: more than INT_MAX triangles");
  const long long nv = static_cast<long long>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const int v : mesh.triangles[t])
      if (v < 0 || v >= nv)
        throw std::invalid_argument("find_self_intersections: triangle " + std::to_string(t) +
                                    " has vertex index " + std::to_string(v) + " out of range");
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (!mesh.vertices[v].allFinite())
      throw std::invalid_argument("find_self_intersections: vertex " + std::to_string(v) +
                                  " has a non-finite coordinate");
}

// For each vertex, the smallest index of a vertex at the same position (operator== on the
// coordinates, so -0.0 and +0.0 are one position).
std::vector<int> canonical_vertices(const TriangleMesh& mesh) {
  const std::vector<Eigen::Vector3d>& p = mesh.vertices;
  std::vector<int> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  const auto less = [&p](int a, int b) {
    const Eigen::Vector3d &u = p[static_cast<std::size_t>(a)], &v = p[static_cast<std::size_t>(b)];
    if (u.x() != v.x()) return u.x() < v.x();
    if (u.y() != v.y()) return u.y() < v.y();
    if (u.z() != v.z()) return u.z() < v.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> canonical(p.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t v = static_cast<std::size_t>(order[i]);
    const bool same_as_previous =
        i > 0 && p[v] == p[static_cast<std::size_t>(order[i - 1])];  // -0.0 == +0.0
    canonical[v] =
        same_as_previous ? canonical[static_cast<std::size_t>(order[i - 1])] : static_cast<int>(v);
  }
  return canonical;
}

// Whether the segment ab meets the triangle t. Boxes first: comparing coordinates is exact
// and cheap, and settles most of the candidates of a fan (triangles around one vertex,
// whose boxes all meet there), which CGAL's test would otherwise take to its exact
// arithmetic when the triangles are coplanar.
bool segment_meets(const Point& a, const Point& b, const std::array<Point, 3>& t) {
  if (!CGAL::do_overlap(a.bbox() + b.bbox(), t[0].bbox() + t[1].bbox() + t[2].bbox())) return false;
  return CGAL::do_intersect(Triangle(t[0], t[1], t[2]), Segment(a, b));
}

// The exact test of the file comment for two non-degenerate triangles, given their
// corners and the canonical vertex of each corner.
bool intersect_beyond_shared(const std::array<Point, 3>& t, const std::array<int, 3>& tv,
                             const std::array<Point, 3>& u, const std::array<int, 3>& uv) {
  int shared = 0;
  std::array<int, 3> match{-1, -1, -1};  // match[i]: corner of u at corner i of t, or -1
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (tv[static_cast<std::size_t>(i)] == uv[static_cast<std::size_t>(j)]) {
        match[static_cast<std::size_t>(i)] = j;
        ++shared;
      }
  switch (shared) {
    case 0:
      return CGAL::do_intersect(Triangle(t[0], t[1], t[2]), Triangle(u[0], u[1], u[2]));
    case 1: {
      const int i = static_cast<int>(
          std::find_if(match.begin(), match.end(), [](int m) { return m >= 0; }) - match.begin());
      const int j = match[static_cast<std::size_t>(i)];
      return segment_meets(t[static_cast<std::size_t>((i + 1) % 3)],
                           t[static_cast<std::size_t>((i + 2) % 3)], u) ||
             segment_meets(u[static_cast<std::size_t>((j + 1) % 3)],
                           u[static_cast<std::size_t>((j + 2) % 3)], t);
    }
    case 2: {
      // a, b: the shared corners; c, d: the third corners of t and u.
      const int ic = static_cast<int>(std::find(match.begin(), match.end(), -1) - match.begin());
      const int jd = 3 - match[static_cast<std::size_t>((ic + 1) % 3)] -
                     match[static_cast<std::size_t>((ic + 2) % 3)];
      const Point& a = t[static_cast<std::size_t>((ic + 1) % 3)];
      const Point& b = t[static_cast<std::size_t>((ic + 2) % 3)];
      const Point& c = t[static_cast<std::size_t>(ic)];
      const Point& d = u[static_cast<std::size_t>(jd)];
      return CGAL::coplanar(a, b, c, d) && CGAL::coplanar_orientation(a, b, c, d) == CGAL::POSITIVE;
    }
    default:  // the same triangle twice: a pair when wound alike (a doubled surface), not
              // when wound oppositely (the face two glued solids share)
      return match[1] == (match[0] + 1) % 3;
  }
}

}  // namespace

// Method. Bounding boxes of the non-degenerate triangles (closed boxes, so touching boxes
// are candidates), candidate pairs from CGAL's box_self_intersection_d, then the exact
// test on each candidate with OpenMP threads, 2^20 candidates at a time: memory stays
// linear in the triangles (plus the pairs found) even where the candidates are quadratic,
// as in a fan of n triangles around one vertex (the way CAD tools cap a cylinder), whose
// n^2 / 2 triangle pairs all have meeting boxes. The reference is CGAL's
// Polygon_mesh_processing::self_intersections, whose test for triangles sharing one or two
// corners this is; it is not used because CGAL 5.5 offers it only for halfedge meshes,
// which cannot hold non-manifold edges (the meshes medspheres must accept have them), and
// it reports each degenerate triangle as a pair with itself.
//
// Why the definitions (self_intersection.h). One shared corner p: for non-degenerate
// triangles, "some point other than p is common" is equivalent to "the edge of t opposite
// p meets u, or the edge of u opposite p meets t". Two shared corners: triangles that
// share an edge and are not coplanar meet only along it. Three: the same triangle wound
// alike doubles the surface, as where two overlapping solids share part of a face, and
// the enclosed volume counts the region behind it twice; wound oppositely it is the face
// two glued solids share (two tetrahedra joined by a face), and the volume and the winding
// number are those of their union. So two boxes pressed face to face intersect where their
// faces overlap, unless the faces are triangulated alike.
//
// Cost: the box search is sequential (CGAL runs it in parallel only with TBB, which
// medspheres does not use) and takes most of the time; the exact tests are parallel, and
// most candidates of a fan are settled by comparing the boxes of an edge and a triangle
// before any exact predicate. Figures in docs/measuring.md.
SelfIntersections find_self_intersections(const TriangleMesh& mesh, int threads) {
  const int nt = thread_count(threads);
  check_mesh(mesh);
  const std::vector<int> canonical = canonical_vertices(mesh);
  const std::size_t n = mesh.triangles.size();

  // Corners and canonical vertices of every triangle; boxes of the non-degenerate ones.
  std::vector<std::array<Point, 3>> corners(n);
  std::vector<std::array<int, 3>> ids(n);
  std::vector<Box> boxes;
  boxes.reserve(n);
  SelfIntersections out;
  for (std::size_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::size_t v =
          static_cast<std::size_t>(mesh.triangles[t][static_cast<std::size_t>(k)]);
      const Eigen::Vector3d& p = mesh.vertices[v];
      corners[t][static_cast<std::size_t>(k)] = Point(p.x(), p.y(), p.z());
      ids[t][static_cast<std::size_t>(k)] = canonical[v];
    }
    const std::array<Point, 3>& c = corners[t];
    if (CGAL::collinear(c[0], c[1], c[2])) {
      ++out.degenerate_triangles;
      continue;
    }
    boxes.emplace_back(c[0].bbox() + c[1].bbox() + c[2].bbox(), static_cast<int>(t));
  }

  // Candidates: pairs of boxes that meet (closed boxes, so touching ones too). They are
  // tested a full buffer at a time, in parallel, and only the hits are kept: a fan of n
  // triangles around one vertex (a CAD cylinder's cap) has a box pair for every pair of
  // its triangles, n^2 / 2 in all, which are never held at once.
  std::vector<std::array<int, 2>> candidates;
  std::vector<char> hit;
  const auto test_candidates = [&] {
    hit.assign(candidates.size(), 0);
    const long long nc = static_cast<long long>(candidates.size());
#pragma omp parallel for schedule(dynamic, 256) num_threads(nt)
    for (long long c = 0; c < nc; ++c) {
      const std::array<int, 2>& pr = candidates[static_cast<std::size_t>(c)];
      const std::size_t i = static_cast<std::size_t>(pr[0]), j = static_cast<std::size_t>(pr[1]);
      hit[static_cast<std::size_t>(c)] =
          intersect_beyond_shared(corners[i], ids[i], corners[j], ids[j]);
    }
    for (std::size_t c = 0; c < candidates.size(); ++c)
      if (hit[c]) out.pairs.push_back(candidates[c]);
    candidates.clear();
  };
  std::vector<const Box*> box_pointers;
  box_pointers.reserve(boxes.size());
  for (const Box& b : boxes) box_pointers.push_back(&b);
  CGAL::box_self_intersection_d<CGAL::Sequential_tag>(
      box_pointers.begin(), box_pointers.end(),
      [&](const Box* a, const Box* b) {
        const int i = a->info(), j = b->info();
        candidates.push_back(i < j ? std::array<int, 2>{i, j} : std::array<int, 2>{j, i});
        if (candidates.size() == kCandidateBuffer) test_candidates();
      },
      kBoxCutoff);
  test_candidates();
  // The box search reports pairs in an order of its own: sorted, the result is the same
  // for every thread count (and every buffer size).
  std::sort(out.pairs.begin(), out.pairs.end());
  return out;
}

}  // namespace medspheres
