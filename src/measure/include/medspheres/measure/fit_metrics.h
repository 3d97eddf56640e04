#pragma once
/// \file
/// Fit metrics: how well a set of balls S approximates the solid Omega bounded by a mesh.
/// The paper's normalized volumetric error nerr (section 4.1), a Monte-Carlo estimate of the
/// true error with its 95% interval (any mesh, any set), and how far the surface lies outside
/// the union (what a collision checker misses).
///
/// Frame and units: the mesh and the balls share frame M and its unit; L is the largest side
/// of the mesh's bounding box. The mesh is oriented first (on a copy). V = vol(Omega) is
/// defined when every component is closed; inside means a winding number > 0.5.
/// Protrusion of a ball (c, r): r - s d, d the exact distance from c to the mesh (holes capped
/// on an open mesh), s = +1 for c inside and -1 outside.
/// nerr kinds, decided in this order: undefined (no positive V; nerr NaN), approximate (the
/// mesh intersects itself), exact (no protrusion above kProtrusionTolerance L; the true
/// error lies in [nerr, nerr + nerr_slack]), lower_bound (otherwise).
/// Determinism: every number but the timings is bit-identical for every thread count.
/// Errors: InputError (source "sphere set") for an empty or invalid set, or one whose box has
/// no finite volume; std::invalid_argument for options out of range or an unusable mesh.
/// Thread safety: a FitEvaluator is immutable after construction.
/// The definitions, the tolerances and the intervals are derived in fit_metrics.cpp.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/measure/self_intersection.h"
#include "medspheres/measure/union_volume.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/sphere_set.h"
#include "medspheres/threads.h"
#include "medspheres/triangle_mesh.h"

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
  struct Solid;  // the oriented mesh, its report and self-intersections (fit_metrics.cpp)
  static Solid prepare(const TriangleMesh& mesh, int threads);
  explicit FitEvaluator(Solid solid);

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
