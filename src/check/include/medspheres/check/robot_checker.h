#pragma once
/// \file
/// RobotChecker: collision checks of a robot's sphere sets at planner speed. Many joint
/// configurations at once, four to a block, one per SIMD lane (AVX2 where the processor
/// has it, a scalar path with the same arithmetic elsewhere); every answer is the same bit
/// for bit on either path and for any number of threads.
///
/// Input: a robot file's model (robot_model.h; the planner's K spheres per link: the
/// covering set "outer" and the inner set), optionally a second model of the same robot
/// with larger sets baked once (the fine level), and a Scene (scene.h). The robot is posed
/// by its own forward kinematics (forward_kinematics.h conventions: q in
/// KinematicTree::joint_names() order, radians and metres, base pose X_WB).
///
/// Colliding means within the margin: distance <= margin, so touching (distance 0)
/// collides at margin 0. Two modes:
/// - Mode::spheres: a configuration collides when a sphere of a link's covering set (its
///   inner set for a link without one) is within the margin of a scene element or of such
///   a sphere of a link it is paired with for self-collision; the test is
///   |c - x|^2 <= (r + margin)^2 in doubles for the element's nearest point x (its core's,
///   for a sphere or a capsule, with the radius added), |c1 - c2|^2 <= (r1 + r2 + margin)^2
///   for two spheres: the same answers as those tests run over every sphere and element.
/// - Mode::bounds: certified three-valued verdicts, the links' solids standing between
///   their sets (bounded_geometry.h in fcl_adapter argues it): free when every pair is
///   free, a pair free when its covering spheres are all farther than margin + allowance()
///   from the other side; colliding when some pair's inner spheres come within margin -
///   allowance(); else undecided. The planner's sets first, then the fine sets. Certified
///   only when the covering sets are certified covers (the fcl_adapter's
///   CertifiedChecker checks their certificates and settles undecided pairs with meshes).
///   allowance() exceeds the rounding of these computations (forward kinematics
///   included) by orders of magnitude; see docs/checker.md.
/// Both modes first test each link's bounding sphere (holding all its sets) against a
/// lower bound of the distance to the scene, and to the other link's: a shortcut that
/// changes no answer.
///
/// Self-collision pairs: every two links with spheres except the two links of a joint and
/// the pairs CheckerOptions::disabled (an SRDF's <disable_collisions>, or the ignored
/// pairs of a self-collision matrix).
///
/// Edges: the configurations q(t_k) = q0 + t_k (q1 - q0), t_k = k / n, k = 0 ... n, with
/// n = max(1, ceil(|q1 - q0| / resolution)) (Euclidean norm over the joints; at most
/// kMaxEdgeSteps, else std::invalid_argument naming the edge before any work), are checked
/// in VAMP's rake order: the k split into kLanes runs of consecutive samples, one run per
/// lane, all runs stepped together, stopping at the first colliding one.
///
/// Errors: InputError (source "robot checker") for a fine model that is not the planner's
/// robot, a disabled pair naming an unknown link, or bad CheckerOptions::inner_points;
/// std::invalid_argument for a margin or resolution that is negative or not finite, a configuration
/// with a non-finite entry or one beyond +-1e6 (the reduction of angles is exact below 2^26), or
/// Simd::avx2 on a processor without it. Threads: immutable after construction; every const member
/// may run from many threads at once.

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "medspheres/check/scene.h"
#include "medspheres/robot_model.h"

namespace medspheres::check {

/// The most configurations one edge may check (robot_checker.h's edges).
inline constexpr std::size_t kMaxEdgeSteps = 1'000'000'000;

enum class Mode { spheres, bounds };
enum class Verdict : std::uint8_t { free = 0, colliding = 1, undecided = 2 };
enum class Simd { automatic, scalar, avx2 };

struct CheckerOptions {
  double margin = 0.0;  ///< m, finite, >= 0: colliding means distance <= margin
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  ///< the root link's pose in W
  /// Link pairs left out of self-collision, in either order.
  std::vector<std::pair<std::string, std::string>> disabled;
  bool self = true;             ///< check self-collision pairs
  Simd simd = Simd::automatic;  ///< AVX2 when the processor has it
  /// Every test in floats first, eight configurations at once, the unsure ones again in
  /// doubles (the same verdicts; false: doubles only).
  bool float_tests = true;
  double cell = 0.0;                 ///< m: the scene grid's cell side (0: half the reach)
  std::size_t max_cells = 1u << 22;  ///< the grid's cells at most (the side grows to fit)
  /// Threads that build the scene's grid and distance field, here and in with_scene():
  /// 0 for every core, else 1 to kMaxThreads (medspheres/threads.h). The checker built is
  /// the same for any count.
  int build_threads = 0;
  /// The order of the tests (a link against the scene, a self pair; in the bounds mode
  /// within each level): at construction, this many configurations drawn within the
  /// joints' limits (sample_configurations.h, seed order_seed) are checked in the spheres
  /// mode, and the tests that found them colliding most often run first, so that a
  /// colliding configuration stops sooner; the bounds mode's order, likewise, from the
  /// tests that proved them colliding, and its probe (TestOrder). 0: each link against the
  /// scene, then each self pair, no probe. The verdicts (and undecided pairs) are the same
  /// for every order.
  std::size_t order_samples = 256;
  /// The seed of those configurations. A benchmark that times random configurations should
  /// learn on another seed than it times on, or it times configurations it learnt from.
  std::uint64_t order_seed = 1;
  /// Points (radius 0) or balls of the links' solids, by link name, each in its link's
  /// frame, added to the link's inner set at the planner's level for the bounds mode: each
  /// must lie in its link's closed solid (a mesh vertex, an inner ball; the caller vouches
  /// for it, as for the inner sets), so that two of them within the margin prove the pair
  /// colliding. For a link whose inner set lies in its filled solid (LinkSpheres::
  /// inner_filled), they are its inner set. The spheres mode does not see them. The
  /// fcl_adapter's CertifiedChecker passes its learnt witnesses here
  /// (FallbackOptions::kernel_witnesses). InputError for an unknown link, a link without a
  /// covering set (its inner set is the spheres mode's), or a point or radius that is not
  /// finite or a radius < 0.
  std::map<std::string, std::vector<Sphere>> inner_points;
  /// Joint-space tables of the self pairs whose relative pose hangs on at most three joint
  /// positions with finite limits: at construction, a grid of at most this many cells per
  /// pair over those positions, a cell marked free when the pair's spheres-mode sets are
  /// proven farther apart than margin + max(allowance(), 1e-6 m) at every configuration in
  /// it (the sets' gap at the cell's centre less a bound of how far the cell's joints move
  /// them; the 1e-6 lets with_scene() share the tables with any scene within about 1 km).
  /// The spheres mode skips such a pair in a configuration that falls in a free cell (the
  /// bounds mode does not use them). 0: none. The verdicts are the same with or without.
  std::size_t pair_table_cells = 1u << 16;
};

/// A pair left undecided by the bounds: `link` indexes links(); `other` is a link index
/// (self) or a scene object index.
struct UndecidedPair {
  std::size_t link = 0, other = 0;
  bool self = false;
};

/// The scene grid's size, for reports.
struct GridStats {
  double cell_side = 0.0;
  std::size_t cells = 0, entries = 0, elements = 0;
  /// The links that no configuration brings within the margin of the scene (revolute
  /// joints at any angle): their scene tests are skipped.
  std::size_t far_links = 0;
};

/// The order the checker runs its tests in (CheckerOptions::order_samples), for reports:
/// per test, a link index (the link against the scene) or links().size() + k for self
/// pair k of self_pairs(); `head`: how many of them run before the links' bounding spheres
/// are tested against the scene (the spheres mode; the leading tests that found at least a
/// quarter of the samples colliding). `bounds_tests`: the bounds mode's order (within each
/// level), the tests whose inner sets proved the samples colliding most often first;
/// `probe`: check() of a batch in the bounds mode runs in rounds, round r the tests
/// bounds_tests[probe[r - 1] .. probe[r]) (from 0 in round 0) at the planner's level on the
/// configurations the rounds before left open, regrouped, then every test on those still
/// open (empty: one round, every test).
struct TestOrder {
  std::vector<std::size_t> tests;
  std::size_t head = 0;
  std::vector<std::size_t> bounds_tests;
  std::vector<std::size_t> probe;
};

class RobotChecker {
 public:
  /// \p fine may be null (no fine level). The scene is copied into the checker's grid.
  RobotChecker(const RobotModel& planner, const Scene& scene, const CheckerOptions& options = {},
               const RobotModel* fine = nullptr);
  ~RobotChecker();
  RobotChecker(RobotChecker&&) noexcept;
  RobotChecker& operator=(RobotChecker&&) noexcept;

  /// The same robot, options and fine model against another scene (a planner's next
  /// problem): the self pairs' joint-space tables, which the scene does not change and which
  /// take most of a checker's construction, are shared, not built again. The verdicts are
  /// those of a checker built anew on \p scene.
  RobotChecker with_scene(const Scene& scene) const;

  std::size_t num_positions() const noexcept;
  const std::vector<std::string>& joint_names() const noexcept;
  /// The links with spheres, as UndecidedPair::link indexes them.
  const std::vector<std::string>& links() const noexcept;
  /// The self-collision pairs, indices into links().
  std::vector<std::pair<std::size_t, std::size_t>> self_pairs() const;
  const CheckerOptions& options() const noexcept;
  bool uses_avx2() const noexcept;
  double allowance() const noexcept;  ///< m (see the file comment)
  GridStats grid() const noexcept;
  TestOrder test_order() const;
  /// How many self pairs have a joint-space table (CheckerOptions::pair_table_cells), and
  /// the share of their cells that is free (averaged over the tables; 0 without).
  std::size_t pair_tables() const noexcept;
  double pair_tables_free() const noexcept;

  /// Throws std::invalid_argument (file comment) unless each of the \p n configurations
  /// (rows as below) is finite and within +-1e6.
  void validate(const double* q, std::size_t n) const;

  /// \p n configurations, row-major (n x num_positions()), verdicts into out[0 .. n).
  /// \p threads: 0 for every core, else 1 to kMaxThreads (medspheres/threads.h);
  /// std::invalid_argument otherwise, as for a configuration out of range.
  void check(const double* q, std::size_t n, Mode mode, Verdict* out, int threads = 1) const;
  /// One configuration; in Mode::bounds, the pairs left undecided when it is undecided.
  Verdict check(const double* q, Mode mode, std::vector<UndecidedPair>* undecided = nullptr) const;
  /// Mode::bounds for \p n configurations (rows as above) with the pairs each leaves
  /// undecided: undecided[i] (cleared first) receives those of configuration i when out[i]
  /// is undecided, as the one-configuration check() gives them (the same verdicts as
  /// check()'s), eight configurations to a block, as check() runs them (the probe's rounds
  /// too): a whole batch's verdicts and the undecided ones' pairs in one call. The pairs
  /// are those of the tests in doubles: a lane whose float tests were all certain gives its
  /// pairs from them (each test has the same outcome in doubles), except that a link's
  /// scene objects are then those within the float tests' slack more of its posed
  /// covering spheres (a few more objects, never fewer).
  void check_bounds(const double* q, std::size_t n, Verdict* out,
                    std::vector<UndecidedPair>* undecided, int threads = 1) const;

  /// Whether some of the \p n configurations (rows as above) collides in Mode::spheres:
  /// what a planner's own motion validation asks of the samples it chose (VAMP's rake).
  /// Eight at a time in the order given; a block stops at the first lane found colliding,
  /// so the answer is that of check() in fewer tests. Throws what check() would.
  bool any_colliding(const double* q, std::size_t n) const;

  /// \p n edges from q0[i] to q1[i] (rows as above); returns the configurations checked.
  std::size_t check_edges(const double* q0, const double* q1, std::size_t n, double resolution,
                          Mode mode, Verdict* out, int threads = 1) const;
  /// One edge: colliding at the first colliding sample; in Mode::bounds undecided when no
  /// sample collides and some is undecided (their t_k appended to \p undecided_t, in the
  /// order checked). \p checked, when given, receives the configurations checked.
  Verdict check_edge(const double* q0, const double* q1, double resolution, Mode mode,
                     std::vector<double>* undecided_t = nullptr,
                     std::size_t* checked = nullptr) const;
  /// The n of an edge (file comment).
  std::size_t edge_steps(const double* q0, const double* q1, double resolution) const;
  /// Throws what check_edges() would for these \p n edges (their configurations, the
  /// resolution, each edge's n), before any work.
  void validate_edges(const double* q0, const double* q1, std::size_t n, double resolution) const;

 private:
  RobotChecker(const RobotChecker& donor, const Scene& scene);  // with_scene()

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace medspheres::check
