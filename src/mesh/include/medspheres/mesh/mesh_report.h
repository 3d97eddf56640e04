#pragma once
/// \file
/// Validation of a triangle mesh: what it is made of, whether it bounds a solid, and
/// the one repair medspheres makes (orientation).
///
/// Definitions, exact on vertex indices (no tolerance: two vertices at one position are
/// one only if the loader merged them, see mesh_io.h):
/// - an edge is an unordered pair of distinct vertex indices used by some triangle; a
///   boundary edge is used by exactly one triangle, a non-manifold edge by three or more;
/// - a degenerate triangle has a repeated vertex index (collapsed: no edges, in no
///   component) or zero area in double (|(b - a) x (c - a)| == 0; such a sliver with
///   three distinct vertices counts like any other triangle);
/// - components are the classes of non-collapsed triangles connected through shared
///   edges; a component is closed when none of its edges is boundary or non-manifold,
///   and the mesh is closed when every component is;
/// - signed volume is (1/6) sum over triangles of a . (b x c): the enclosed volume of a
///   closed, consistently outward-wound component, merely a number otherwise.

#include <cstddef>
#include <string>
#include <vector>

#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// Orientation of one component.
enum class Orientation {
  kOutward,       ///< closed, consistently wound, positive signed volume
  kInward,        ///< closed, consistently wound, negative signed volume
  kInconsistent,  ///< some edge is traversed in the same direction by its two triangles
  kOpen,          ///< has boundary or non-manifold edges: no inside to point to
};

const char* to_string(Orientation o);

struct ComponentReport {
  std::size_t triangles = 0;
  std::size_t boundary_edges = 0;
  std::size_t nonmanifold_edges = 0;
  bool closed = false;
  double signed_volume = 0.0;
  Orientation orientation = Orientation::kOpen;
  /// kInward and inside an odd number of the other closed, consistently wound
  /// components: the wall of a cavity, which is rightly wound inward (see orient_mesh).
  bool cavity = false;
};

struct MeshReport {
  std::size_t triangles = 0;  ///< all of them, collapsed ones included
  std::size_t vertices = 0;   ///< vertices used by at least one triangle
  std::size_t unreferenced_vertices = 0;
  std::size_t edges = 0;
  std::size_t components = 0;
  std::size_t boundary_edges = 0;
  std::size_t nonmanifold_edges = 0;
  std::size_t degenerate_triangles = 0;
  std::size_t collapsed_triangles = 0;  ///< degenerate with a repeated vertex index
  std::size_t inconsistent_edges = 0;   ///< manifold edges whose two triangles disagree on winding
  bool closed = false;                  ///< no boundary and no non-manifold edges
  double signed_volume = 0.0;           ///< sum over all triangles, see file comment
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();  ///< of referenced vertices
  Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
  std::vector<ComponentReport> component_reports;  ///< in order of first triangle index

  /// The largest side of the bounding box (L, the scale of every relative length).
  double largest_side() const { return (bbox_max - bbox_min).maxCoeff(); }

  /// True when every component is closed and wound outward, or inward as the wall of a
  /// cavity: the precondition for an exact enclosed volume and an exact inside test.
  bool is_closed_outward() const;
};

/// Analyses \p mesh. Never throws on bad geometry: it only describes it.
/// Precondition: every index is in range (throws std::invalid_argument otherwise).
MeshReport analyze_mesh(const TriangleMesh& mesh);

/// analyze_mesh(mesh).closed && analyze_mesh(mesh).inconsistent_edges == 0, in about a
/// third of its memory (24 bytes per triangle): every edge is used by exactly two
/// triangles, in opposite directions (collapsed triangles have no edges).
/// Precondition: every index is in range (throws std::invalid_argument otherwise).
bool is_closed_consistent(const TriangleMesh& mesh);

/// What orient_mesh changed.
struct OrientationFix {
  std::size_t triangles_flipped_for_consistency = 0;  ///< minority-wound triangles of
                                                      ///< edge-manifold components
  std::size_t components_flipped_outward = 0;         ///< closed components turned outward
                                                      ///< (cavities are kept, see below)
};

/// Makes the winding of each edge-manifold component consistent (flipping the smaller
/// set of triangles), then turns closed components with negative signed volume outward,
/// except cavities: such a component C is flipped only when an even number (0, 2, ...)
/// of the other closed, consistently wound components contain it, where "D contains C"
/// means |winding number of D alone| > 0.5 at the centroid of C's largest triangle.
/// Components of positive volume are never flipped; components with non-manifold edges
/// are left alone. Nesting is assumed proper (for crossing shells the test point
/// decides). Deterministic.
OrientationFix orient_mesh(TriangleMesh& mesh);

/// The boundary of the mesh as chains of vertex indices: every boundary edge (used by
/// exactly one triangle) exactly once, directed as in its triangle, chained head to tail
/// from the lowest unused edge. Where several boundary edges leave one vertex (a
/// non-manifold boundary), a chain takes the lowest unused one. A chain usually closes
/// (its last vertex leads back to its first); one that cannot is returned open. Empty
/// for a closed mesh. Deterministic.
std::vector<std::vector<int>> boundary_loops(const TriangleMesh& mesh);

/// Checks that a mesh can be used at all: at least one triangle, finite coordinates of
/// magnitude at most kMaxCoordinate, indices in range, and not every triangle degenerate.
/// (Every exact query squares lengths; beyond kMaxCoordinate a square overflows.)
/// \throws InputError naming \p source and the first problem found.
void check_mesh_usable(const TriangleMesh& mesh, const std::string& source);

/// The largest coordinate magnitude check_mesh_usable accepts: the squared distance of
/// two such points, 12 * 1e300, is a finite double.
inline constexpr double kMaxCoordinate = 1e150;

}  // namespace medspheres
