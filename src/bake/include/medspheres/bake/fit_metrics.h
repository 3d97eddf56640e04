#pragma once
/// \file
/// Fit metrics: how well a set of balls S approximates the solid Omega bounded by a
/// triangle mesh. The paper's normalized volumetric error (section 4.1), exact or a lower
/// bound, and beyond the paper a Monte-Carlo estimate of the true error that holds for any
/// set, and how far the mesh surface lies outside the union (what a collision checker
/// misses).
///
/// Frames and units. The mesh and the balls share one frame M and one unit of length.
/// Lengths are reported in that unit, volumes in units^3, areas in units^2. L denotes the
/// largest side of the mesh's bounding box.
///
/// The solid. The mesh is oriented first (orient_mesh on a copy: consistent winding,
/// closed components turned outward), so a raw mesh is measured like a loaded one.
/// - vol(Omega) = V is defined when every component is closed (see mesh_report.h): it is
///   the sum of the components' divergence-theorem volumes, each positive once oriented,
///   i.e. the integral of the winding number. That is the volume of the solid when the
///   surface does not intersect itself and components do not nest; a region inside two
///   components, or enclosed twice by a surface that passes through itself, is counted
///   twice (the Monte Carlo below measures how much, and FitReport::warnings says so). The
///   volume of an open mesh is not defined, and neither is nerr.
/// - The mesh self-intersects when two of its triangles meet other than at the vertices and
///   edges they share (self_intersection.h; touching counts). FitEvaluator finds the pairs
///   once, at construction.
/// - Inside means a generalized winding number > 0.5 (mesh_query.h). For a closed mesh
///   this is Omega; for an open one it is the solid its winding number defines, the solid
///   the baker fills, and the one the Monte-Carlo estimate measures.
///
/// Protrusion of a ball (c, r): r - s d, with d the exact distance from c to the mesh and
/// s = +1 when c is inside, -1 when not (a ball whose centre is outside protrudes by
/// r + d). For a closed mesh it is <= 0 exactly when the ball lies in the closed solid.
/// For an open mesh d is the distance to the mesh with its holes capped
/// (MeshQueryOptions::cap_holes), so that a ball reaching out through a hole protrudes.
///
/// nerr (paper section 4.1), with U = vol(S) exact (union_volume.h) and
/// Err = vol(S \ Omega) + vol(Omega \ S):
/// - kind "exact" when no protrusion exceeds the tolerance t = kProtrusionTolerance L:
///   nerr = (V - U) / V. A ball protruding by t_i <= t has its outside part in a shell of
///   thickness t_i, so 0 <= Err / V - nerr <= nerr_slack = 2 sum_i 4 pi r_i^2 max(t_i, 0)
///   / V, which VolumeError reports (0 for baked sets: their protrusions are negative);
/// - kind "lower_bound" otherwise: nerr = |V - U| / V <= Err / V (Lemma 1);
/// - kind "approximate" when the mesh self-intersects: nerr is the value of the two rules
///   above, but V may count the regions where parts of the surface overlap as often as they
///   are covered, so it is neither exact nor a bound (two parts that only touch leave V
///   exact; the pairs do not tell, the Monte-Carlo multiply covered volume does). A warning
///   names the number of intersecting pairs;
/// - kind "undefined" when V is not defined or not positive: nerr is NaN.
/// The kinds are decided in the order undefined, approximate, exact / lower_bound.
/// The tolerance: the baker shrinks radii by 1e-12 L + 4 eps (X + L), X the largest
/// |coordinate| of the box (bake.h), so its spheres protrude by about minus that, give
/// or take the rounding of the distance (a few ulps of the coordinates).
/// kProtrusionTolerance = 1e-9 also accepts sets rounded to 12 significant digits (for
/// coordinates up to about 100 L from the origin); the error it can hide is bounded by
/// nerr_slack <= 2 t A / V, A the balls' total sphere area, and is reported rather than
/// assumed.
///
/// Monte-Carlo error (any mesh, any set). N points uniform in the box B that bounds both
/// the mesh and the balls; point i comes from a counter-based generator keyed by the seed
/// and i, so the points do not depend on the thread count. Each point is classed as in
/// Omega (winding number > 0.5) and in S (some closed ball). On a closed mesh two cases
/// need no winding-number query, and get the exact winding number: a point in a ball of
/// protrusion <= 0 whose centre has winding number 1 (the surface does not cross the
/// ball), and a point in a cell of a grid over B whose centre is farther from the surface
/// than the cell's half diagonal (the surface does not cross the cell, so the winding
/// number, an integer, is the one at the centre; about one cell per 16 points). The
/// fraction p^ of points in exactly one of Omega and S estimates p = Err / vol(B).
/// - Closed mesh: estimate vol(B) p^ / V, with the 95% Wilson score interval for p scaled
///   the same way. Wilson, because p is small (the error is a thin layer of the solid):
///   the normal-approximation interval p^ +- 1.96 sigma then undercovers and shrinks to a
///   point when no point is hit, while Wilson's keeps close to 95% coverage for small p
///   and stays within [0, 1].
/// - Open mesh: V is not defined, so the error is normalized by the volume of the winding
///   solid estimated from the same points. The estimate is a ratio of two means; its
///   interval is the estimate +- 1.96 sigma, sigma from the delta method.
/// sigma, the standard error of the estimate, is reported with each interval.
///
/// Coverage of the surface. sample_surface draws area-weighted points on the mesh (the
/// same points for a seed) and appends every vertex used by a triangle; point_coverage
/// gives, for each point, its distance to the union (0 when it lies in a ball). The max is
/// over samples and vertices; the mean and the 95th percentile are over the area-weighted
/// samples alone, where they estimate the mean and the percentile over the surface
/// (vertices crowd where the tessellation is fine, which would bias them).
///
/// Determinism. For given inputs and seed every number reported, except the timings, is
/// bit-identical for every thread count: each point's work is independent, counts are
/// integers, and sums run in index order.
///
/// Errors. An empty ball list, or a ball with a non-finite coordinate, a radius not
/// finite and > 0 or a bounding box that is not finite (validate_sphere_set), throws
/// InputError with source "sphere set"; so does, in evaluate(), a set reaching so far
/// that the box B has no finite volume. Subnormal radii are valid. Options out of range
/// throw std::invalid_argument naming the option. A mesh without triangles, with non-finite
/// coordinates or bad indices throws std::invalid_argument (as MeshQuery does).
///
/// Thread safety: a FitEvaluator is immutable after construction; its const members may
/// be called from several threads at once.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/mesh/mesh_query.h"
#include "medspheres/bake/self_intersection.h"
#include "medspheres/sphere_set.h"
#include "medspheres/mesh/threads.h"
#include "medspheres/triangle_mesh.h"
#include "medspheres/bake/union_volume.h"

namespace medspheres {

/// "No ball protrudes" means no protrusion exceeds this times L (see the file comment).
inline constexpr double kProtrusionTolerance = 1e-9;

struct FitOptions {
  std::size_t volume_samples = 1000000;  ///< Monte-Carlo points (>= 1); sigma ~ 1/sqrt(N)
  std::size_t surface_samples = 100000;  ///< area-weighted surface points (>= 1); plus vertices
  std::uint64_t seed = 1;                ///< the points drawn, whatever the thread count
  int threads = 0;                       ///< 0: all cores; at most kMaxThreads
};

/// What nerr is (file comment).
enum class NerrKind { kExact, kLowerBound, kApproximate, kUndefined };

/// "exact", "lower_bound", "approximate" or "undefined".
const char* to_string(NerrKind kind);

/// The paper's volumetric error and the protrusions it depends on.
struct VolumeError {
  std::optional<double> mesh_volume;  ///< V, when defined
  UnionMeasures union_measures;       ///< U = union_measures.volume, its area, hidden balls
  std::vector<double> protrusions;    ///< one per ball, in input order
  double max_protrusion = 0.0;        ///< the largest of them
  int max_protrusion_ball = -1;       ///< its index (the smallest on ties)
  std::size_t protruding = 0;         ///< balls protruding by more than the tolerance
  double protrusion_tolerance = 0.0;  ///< t = kProtrusionTolerance L
  double nerr = std::numeric_limits<double>::quiet_NaN();
  NerrKind kind = NerrKind::kUndefined;
  double nerr_slack = 0.0;  ///< kind exact: Err / V lies in [nerr, nerr + nerr_slack]; else 0
  /// Pairs of triangles of the mesh that intersect (self_intersection.h); when V is defined
  /// and this is > 0, kind is approximate.
  std::size_t self_intersecting_pairs = 0;
};

/// A Monte-Carlo estimate with its 95% interval [lo, hi] and standard error sigma.
struct Estimate95 {
  double estimate = std::numeric_limits<double>::quiet_NaN();
  double lo = std::numeric_limits<double>::quiet_NaN();
  double hi = std::numeric_limits<double>::quiet_NaN();
  double sigma = std::numeric_limits<double>::quiet_NaN();
};

struct MonteCarloError {
  std::size_t samples = 0;
  std::uint64_t seed = 0;
  Eigen::AlignedBox3d box;        ///< B, the region sampled, in frame M
  std::size_t in_solid = 0;       ///< points in Omega
  std::size_t outside_solid = 0;  ///< points in S \ Omega
  std::size_t uncovered = 0;      ///< points in Omega \ S
  /// Err / V for a closed mesh (Wilson interval), Err / vol(winding solid) for an open one
  /// (delta-method interval); see the file comment.
  Estimate95 error;
  bool normalized_by_volume = false;  ///< true: divided by the exact V
  Estimate95 solid_volume;            ///< vol(Omega) from the same points (Wilson)
  double outside_volume = 0.0;        ///< estimate of vol(S \ Omega)
  double uncovered_volume = 0.0;      ///< estimate of vol(Omega \ S)
  /// Closed mesh: the estimate of V - vol(Omega), the integral of (winding number - 1)
  /// where it is >= 2, i.e. the volume of overlapping or nested components counted as many
  /// extra times as it is covered; 0 when no point was found there (then no warning).
  double multiple_volume = 0.0;
  double multiple_volume_sigma = 0.0;  ///< its standard error
};

/// Points on the mesh surface: area-weighted samples first, then the vertices.
struct SurfaceSamples {
  std::vector<Eigen::Vector3d> points;  ///< p_MoP_M
  std::size_t area_samples = 0;         ///< points[0 .. area_samples) are the samples
};

/// How a point lies with respect to the union of the balls.
struct PointCoverage {
  double outside = 0.0;  ///< distance from the point to the union; 0 inside a ball
  /// A ball realizing it: one that contains the point, else the one of least
  /// |p - c| - r (the first found, in an order fixed by the balls and the point).
  int ball = -1;
};

struct CoverageStats {
  std::size_t area_samples = 0;
  std::size_t vertices = 0;
  double max = 0.0;                                  ///< over samples and vertices
  Eigen::Vector3d max_at = Eigen::Vector3d::Zero();  ///< the first point reaching it
  double mean = 0.0;                                 ///< over the area-weighted samples
  /// Over the area-weighted samples, nearest rank: the smallest value that at least 95%
  /// of them do not exceed.
  double p95 = 0.0;
};

/// Wall-clock seconds of each part of evaluate().
struct FitSeconds {
  double union_volume = 0.0;  ///< exact volume and area (CGAL)
  double protrusion = 0.0;    ///< closest points and winding numbers of the centres
  double grid = 0.0;          ///< the grid over the balls used by the next two
  double monte_carlo = 0.0;
  double coverage = 0.0;  ///< surface sampling and distances
  double total = 0.0;
};

struct FitReport {
  std::size_t balls = 0;
  bool mesh_closed = false;  ///< every component closed: V is defined
  VolumeError volume;
  MonteCarloError monte_carlo;
  CoverageStats coverage;
  FitSeconds seconds;
  std::vector<std::string> warnings;  ///< one sentence each, for the user
};

/// V: the divergence-theorem volume of the oriented mesh, when every component is closed
/// and the sum is positive; std::nullopt otherwise.
std::optional<double> solid_volume(const TriangleMesh& mesh);

/// The protrusion of each ball (file comment), with \p threads threads (0: all cores).
/// \p query should be built on an oriented mesh (FitEvaluator::query() is).
/// \throws InputError for invalid balls (source "sphere set").
std::vector<double> sphere_protrusions(const MeshQuery& query, const std::vector<Sphere>& balls,
                                       int threads = 0);

/// \p count area-weighted points on the surface (triangle chosen with probability
/// proportional to its area, then a uniform point in it), then every vertex used by a
/// triangle, in index order. Deterministic for \p seed.
/// \throws std::invalid_argument when count > 0 and the mesh has zero area.
SurfaceSamples sample_surface(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed);

/// For each point, its distance to the union of \p balls and a ball realizing it.
/// \throws InputError for invalid balls (source "sphere set").
std::vector<PointCoverage> point_coverage(const std::vector<Sphere>& balls,
                                          const std::vector<Eigen::Vector3d>& points,
                                          int threads = 0);

/// Max over all points; mean and p95 over the area-weighted samples (0 when there are
/// none). Precondition: coverage.size() == samples.points.size().
CoverageStats summarize_coverage(const SurfaceSamples& samples,
                                 const std::vector<PointCoverage>& coverage);

/// Holds the oriented mesh, its query structure and its volume, for evaluating many sets.
class FitEvaluator {
 public:
  /// Orients a copy of \p mesh, builds its MeshQuery, computes V and finds the pairs of
  /// triangles that intersect (find_self_intersections with \p threads threads, 0: all
  /// cores).
  /// \throws std::invalid_argument for threads outside [0, kMaxThreads].
  explicit FitEvaluator(const TriangleMesh& mesh, int threads = 0);

  const MeshQuery& query() const noexcept { return query_; }
  /// V (see solid_volume).
  const std::optional<double>& volume() const noexcept { return volume_; }
  /// True when every component is closed.
  bool closed() const noexcept { return closed_; }
  /// kProtrusionTolerance L.
  double protrusion_tolerance() const noexcept { return tolerance_; }
  /// The intersecting pairs of triangles of the mesh (self_intersection.h).
  const SelfIntersections& self_intersections() const noexcept { return self_intersections_; }

  /// Union measures, protrusions and nerr: the part of evaluate() the paper defines.
  VolumeError volume_error(const std::vector<Sphere>& balls, int threads = 0) const;

  /// Every metric of the file comment.
  /// \throws std::invalid_argument for volume_samples or surface_samples 0, threads outside
  ///   [0, kMaxThreads].
  FitReport evaluate(const std::vector<Sphere>& balls, const FitOptions& options = {}) const;

 private:
  VolumeError combine(const std::vector<Sphere>& balls, UnionMeasures measures,
                      std::vector<double> protrusions) const;

  MeshQuery query_;
  std::optional<double> volume_;
  bool closed_ = false;
  double tolerance_ = 0.0;
  SelfIntersections self_intersections_;
};

/// One-off FitEvaluator(mesh).evaluate(balls, options).
FitReport evaluate_fit(const TriangleMesh& mesh, const std::vector<Sphere>& balls,
                       const FitOptions& options = {});

}  // namespace medspheres
