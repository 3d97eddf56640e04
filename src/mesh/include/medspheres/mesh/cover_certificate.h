#pragma once
/// \file
/// Certified surface coverage: does the union of a list of closed balls contain every point
/// of every triangle of a mesh?
///
/// Method. A ball is convex, so a triangle lies in it when its three corners do. A triangle
/// none of whose candidate balls contains all three corners is split into four at its edge
/// midpoints, and so on, until every piece lies in one ball or a piece reaches max_depth
/// splits. The pieces of a triangle are exact: their corners have barycentric coordinates
/// k / 2^depth, which doubles hold exactly. Their positions are computed, and the
/// containment test allows for that rounding and its own (derivation in
/// cover_certificate.cpp): a piece is declared inside a ball only when the exact piece is.
/// So "certified" is never wrong; a corner exactly on a sphere, or a triangle that the
/// union's boundary touches, is reported uncertified (within rounding of covered).
///
/// Only the surface is certified. Whether the union also contains the solid's interior is
/// not decided here (a union can cover the surface and leave a void inside).
///
/// Worst uncovered point. For the triangles that are not certified, a best-first search
/// maximises the distance to the union, dist(x) = max(0, min_i |x - c_i| - r_i), over their
/// points: dist is 1-Lipschitz, so a piece whose centroid is at distance f cannot hold a
/// point farther than f plus its circumradius. The search stops when no piece can beat the
/// best point found by more than worst_tolerance (or after max_worst_evaluations points);
/// the reported distance is then within worst_tolerance of the true maximum over the
/// uncertified triangles, up to double rounding.
///
/// Frames and units: those of the mesh and the balls (frame M), which must agree.
/// Determinism: every result but `seconds` is the same for every thread count.
/// Errors: an invalid ball (validate_sphere_set) throws InputError with source "sphere
/// set"; a mesh with non-finite coordinates or bad indices, or options out of range,
/// throw std::invalid_argument. No balls: nothing is certified.
/// Thread safety: a pure function of its arguments.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

struct CoverCertificateOptions {
  int max_depth = 10;  ///< 4-way splits of a triangle at most, in [0, 30]
  /// Uncertified pieces listed at most in CoverCertificate::uncertified_pieces.
  std::size_t max_pieces_reported = 100000;
  /// Worst-point search: stop within this length of the maximum; 0 means 1e-4 of the
  /// largest side of the mesh's bounding box. >= 0.
  double worst_tolerance = 0.0;
  std::size_t max_worst_evaluations = 200000;  ///< points evaluated by that search at most
  int threads = 0;                             ///< 0: all cores (threads.h)
};

/// A piece of a triangle that was not certified: a split piece at max_depth, or the piece
/// in which a corner was found outside every ball (then the triangle is not split
/// further).
struct CoverPiece {
  int triangle = -1;
  std::array<Eigen::Vector3d, 3> corners;  ///< computed positions, frame M
};

struct CoverCertificate {
  bool certified = false;  ///< every triangle lies in the union (mesh with >= 1 triangle)
  std::vector<std::uint8_t> triangle_certified;  ///< 1 when triangle t is certified
  std::size_t triangles = 0;
  std::size_t uncertified_triangles = 0;
  std::size_t pieces_tested = 0;  ///< pieces (triangles included) tested against balls
  int max_depth_reached = 0;      ///< deepest split used by a certified triangle
  /// Uncertified triangles whose search found a corner outside every ball by more than
  /// the rounding of the test: the union certainly misses them.
  std::size_t proven_uncovered_triangles = 0;
  std::vector<CoverPiece> uncertified_pieces;  ///< up to max_pieces_reported, by triangle
  std::size_t uncertified_pieces_total = 0;    ///< all of them, listed or not

  // The worst-point search over the uncertified triangles (none when certified).
  double worst_distance = 0.0;  ///< distance of worst_point to the union, >= 0
  Eigen::Vector3d worst_point = Eigen::Vector3d::Zero();
  int worst_triangle = -1;
  double worst_bound = 0.0;  ///< no point of those triangles is farther than this
  std::size_t worst_evaluations = 0;
  double seconds = 0.0;
};

/// Certifies that the union of \p balls contains every triangle of \p mesh (file comment).
CoverCertificate certify_cover(const TriangleMesh& mesh, const std::vector<Sphere>& balls,
                               const CoverCertificateOptions& options = {});

/// The containment test of the certificate: true only if the closed ball (c, r) contains
/// every point within \p position_error of \p p (p is a computed point whose exact
/// position is at most that far away). Conservative under rounding.
bool ball_contains_certainly(const Sphere& ball, const Eigen::Vector3d& p, double position_error);

}  // namespace medspheres
