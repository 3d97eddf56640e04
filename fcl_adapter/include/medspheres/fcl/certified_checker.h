#pragma once
/// \file
/// CertifiedChecker: the robot checker's certified mode (medspheres/check/robot_checker.h,
/// Mode::bounds) with RobotBounds' mesh fallback, for whole batches of configurations and
/// edges. The levels, cheapest first: each link's bounding sphere, the planner's K spheres
/// (covering and inner sets), the fine sets (a larger cover and inner set per link, baked
/// once), and only for the pairs these leave undecided, decide() of bounded_geometry.h on
/// the links' BoundedGeometry (their sphere trees, with the meshes' surface points), then,
/// when no pair is certainly colliding, settle() by the exact meshes (as robot_collide); a
/// link's mesh against an fcl::OcTree by OctreeCells (octree_cells.h): FCL's mesh-to-box
/// distance on the cells near the link, the leaf tests of FCL's own octree query. Before
/// the meshes, a plane between the two sides' vertices may prove a pair free
/// (separating_plane.h, FallbackOptions::separating_planes).
///
/// Verdicts: colliding when some link pair is within the margin, free when none is, each
/// certified (never a missed collision): by the certified covers and the inner sets, and
/// by exact mesh distance where those cannot tell. Undecided only where a pair has no mesh
/// to settle it (a link without one). Assumed, as in bounded_geometry.h: no solid lies
/// wholly inside another without surface contact.
///
/// Inputs: the planner's model and optionally the fine one (same robot; their covering
/// sets must carry a certificate unless BoundedGeometryOptions::allow_uncertified),
/// optionally the sphere trees' model (FallbackOptions::trees), the
/// exact meshes by link name (link frame), and the scene as FCL objects in W (converted by
/// scene_from_fcl for the spheres; kept as they are for the fallback). Self pairs: as
/// RobotChecker's, with options.disabled.
/// Errors: InputError naming the link for an uncertified cover, and those of RobotChecker,
/// RobotBounds and scene_from_fcl. Threads: immutable after construction; const members
/// may run from many threads at once.

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fcl/narrowphase/collision_object.h>

#include "medspheres/check/robot_checker.h"
#include "medspheres/fcl/octree_cells.h"
#include "medspheres/fcl/pair_joint_table.h"
#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/fcl/scene_from_fcl.h"
#include "medspheres/fcl/separating_plane.h"

namespace medspheres::fcl {

/// What a batch needed besides the spheres.
struct FallbackStats {
  std::size_t table_first = 0;     ///< configurations a table proved colliding, before the bounds
  std::size_t configurations = 0;  ///< configurations that reached the fallback
  std::size_t witnessed = 0;       ///< of these, settled by a witness (no pair walked)
  std::size_t tabled = 0;          ///< pairs a PairJointTable settled
  std::size_t pairs = 0;           ///< pairs given to decide() (the links' sphere trees)
  std::size_t planes = 0;          ///< pairs a separating plane proved free
  std::size_t meshes = 0;          ///< pairs that the exact meshes settled

  FallbackStats& operator+=(const FallbackStats& o) {
    table_first += o.table_first;
    configurations += o.configurations;
    witnessed += o.witnessed;
    tabled += o.tabled;
    pairs += o.pairs;
    planes += o.planes;
    meshes += o.meshes;
    return *this;
  }
};

/// How the fallback is built. None of it changes a verdict, only what it costs.
struct FallbackOptions {
  BoundedGeometryOptions bounds;  ///< of the links' BoundedGeometry
  /// A third model of the same robot whose sets become the links' sphere trees of decide()
  /// (a larger cover and inner set than the fine one, baked once: tighter bounds that
  /// spare mesh queries). Null: the fine sets when given, else the planner's.
  const RobotModel* trees = nullptr;
  /// samples > 0: the pairs and witnesses of RobotBounds' SelfPairOrder (robot_bounds.h,
  /// learnt at construction from seeded configurations at the checker's margin,
  /// CheckerOptions::margin; order.margin is not read): the fallback poses a configuration
  /// the bounds leave undecided and tests every witness first (two points of the links'
  /// solids, inner balls or mesh vertices, certainly within the margin: colliding, before
  /// the bounds are run again for its undecided pairs), then decides its pairs in
  /// robot_collide's order (the self pairs most often colliding first). samples = 0: the
  /// bounds' order, no witnesses.
  SelfPairOrder order;
  /// > 0: every self pair that PairJointTable takes (pair_joint_table.h: its relative pose
  /// hangs on one or two revolute joints) gets a table of at most this many cells, baked at
  /// construction at the checker's margin. check() asks every table that has colliding
  /// cells first (tables_first): a configuration in a colliding cell of one is colliding
  /// without the bounds (the pairs most often colliding first); the fallback asks a
  /// pair's table before its sphere trees. 0: no tables.
  std::size_t table_cells = 0;
  /// With table_cells > 0: > 0 bakes tables for the first this many of
  /// fallback().self_pairs() only (with order.samples > 0, the pairs seen colliding most
  /// often in the order's samples first: those the fallback most often reaches), to bound
  /// the bake; 0: every pair PairJointTable takes.
  std::size_t table_pairs = 0;
  /// With table_cells > 0, non-empty: a folder (PairTableStore, pair_table_store.h) that
  /// keeps the tables: each is read from it when it holds the table of the same pair,
  /// geometry, margin and budget, else baked and written to it. A bake of minutes is then
  /// paid once per robot. Empty: every table is baked at construction.
  std::string table_store;
  /// With tables: check() asks them before the bounds (table_cells). false: the fallback
  /// alone asks them, for the pairs the bounds leave open.
  bool tables_first = true;
  /// With order.samples > 0: the witnesses' two points also join the inner sets of their
  /// links in spheres(), the kernel's planner level (each is an inner ball or a mesh
  /// vertex of its link's solid, so the bounds mode may prove a pair colliding by them as
  /// by any inner sphere; a link without a covering set keeps its inner set, the spheres
  /// mode's). Every witness point of a link is then tested against every inner sphere of
  /// the other link of each pair the covering sets leave open, in the first pass in
  /// floats: the configurations a witness settles no longer reach the fallback, and the
  /// probe (robot_checker.h) learns the pairs they prove; the fallback no longer tests
  /// them (only those of a link the kernel took none for). false: the planner's sets as
  /// they are, the witnesses tested in the fallback only.
  bool kernel_witnesses = true;
  /// Before a pair's exact meshes: a plane between the two sides' vertices
  /// (separating_plane.h: a link's mesh vertices, or its balls when it is made of sphere
  /// primitives; a scene object's vertices, corners or balls), found by GJK on them and
  /// checked with the rounding bounded, that clears the margin proves the pair free, as
  /// the meshes would. false: the meshes settle every pair the trees leave open.
  bool separating_planes = true;
};

class CertifiedChecker {
 public:
  CertifiedChecker(const RobotModel& planner, const RobotModel* fine,
                   const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes,
                   const std::vector<const ::fcl::CollisionObjectd*>& scene,
                   const check::CheckerOptions& options = {}, const FallbackOptions& fallback = {});

  /// The same robot, options and fallback against another scene (a planner's next
  /// problem): what does not depend on the scene is shared, not built again (the
  /// fallback's geometries, learnt order and witnesses, the self pairs' joint-space tables
  /// of FallbackOptions::table_cells, the links' supports for separating planes, and the
  /// kernel's own tables: RobotChecker::with_scene). Only the scene's parts are built: the
  /// kernel's grid and field, an octree's cells, the objects' supports. The verdicts are
  /// those of a checker built anew on \p scene with the same arguments. Errors: those of
  /// the constructor for the scene (scene_from_fcl's).
  CertifiedChecker with_scene(const std::vector<const ::fcl::CollisionObjectd*>& scene) const;

  /// The spheres-only and bounds modes without a fallback.
  const check::RobotChecker& spheres() const noexcept { return checker_; }
  /// The fallback's geometries (the trees' sets when given, else the fine sets when given,
  /// else the planner's; with the meshes).
  const RobotBounds& fallback() const noexcept { return *bounds_; }
  /// The table of the self pair of geometries a and b (indices in fallback().geometries()),
  /// or null (FallbackOptions::table_cells).
  const PairJointTable* table(std::size_t a, std::size_t b) const;

  /// Verdicts of \p n configurations (rows of spheres().num_positions()), \p threads as
  /// RobotChecker::check. \p stats, when given, is added to.
  void check(const double* q, std::size_t n, check::Verdict* out, int threads = 1,
             FallbackStats* stats = nullptr) const;
  check::Verdict check(const double* q, FallbackStats* stats = nullptr) const;

  /// One edge (RobotChecker::check_edge's samples and order); the samples the bounds leave
  /// undecided are settled in the order checked. Returns the verdict; \p checked receives
  /// the configurations checked by the spheres.
  check::Verdict check_edge(const double* q0, const double* q1, double resolution,
                            std::size_t* checked = nullptr, FallbackStats* stats = nullptr) const;
  /// Whether a separating plane proves the pair \p p (as check_bounds names it) free at the
  /// fallback's poses \p X (fallback().poses(q, options().X_WB)), GJK starting from what
  /// decide() gave (\p decided: the inner pair of its upper bound). False without
  /// FallbackOptions::separating_planes, or when a side has no support. True only when the
  /// exact distance of the pair exceeds the margin (separating_plane.h).
  bool plane_free(const check::UndecidedPair& p, const std::vector<::fcl::Transform3d>& X,
                  const CollideResult& decided) const;

  /// \p n edges; returns the configurations checked by the spheres.
  std::size_t check_edges(const double* q0, const double* q1, std::size_t n, double resolution,
                          check::Verdict* out, int threads = 1,
                          FallbackStats* stats = nullptr) const;

 private:
  CertifiedChecker(const RobotModel& planner, const RobotModel* fine,
                   const std::map<std::string, std::shared_ptr<const MeshModel>>& meshes,
                   const std::vector<const ::fcl::CollisionObjectd*>& scene, FclScene converted,
                   const check::CheckerOptions& options, const FallbackOptions& fallback);
  CertifiedChecker(const CertifiedChecker& donor,
                   const std::vector<const ::fcl::CollisionObjectd*>& scene,
                   FclScene converted);  // with_scene()
  using Poses = std::vector<::fcl::Transform3d>;
  using Tables = std::vector<std::unique_ptr<const PairJointTable>>;
  using Supports = std::vector<std::unique_ptr<const VertexSupport>>;
  using CellLinks = std::vector<std::unique_ptr<const OctreeCells::Link>>;
  check::Verdict settle(const double* q, FallbackStats& stats) const;
  Poses poses(const double* q) const;
  bool witnessed(const Poses& X) const;
  // The rows of q among \p n that the bounds left undecided (out[i] undecided) and no
  // witness settles (those become colliding): their indices and poses, in order.
  std::vector<std::size_t> unwitnessed(const double* q, std::size_t n, check::Verdict* out,
                                       std::vector<Poses>& X, int threads,
                                       FallbackStats& stats) const;
  std::vector<check::UndecidedPair> ordered(const std::vector<check::UndecidedPair>& pairs) const;
  check::Verdict settle_pairs(const double* q, const Poses& X,
                              const std::vector<check::UndecidedPair>& pairs,
                              FallbackStats& stats) const;
  bool table_colliding(const double* q) const;
  void check_untabled(const double* q, std::size_t n, check::Verdict* out, int threads,
                      FallbackStats* stats) const;
  Tables bake_tables(const RobotModel& model, std::size_t cells, std::size_t first,
                     const std::string& store_folder) const;
  void make_supports();
  void attach_scene(const CertifiedChecker* donor);

  // What does not depend on the scene and costs to build (bounds_, tables_, cell_links_,
  // supports_) is held by shared pointers, shared by the checkers with_scene() makes; the
  // small indices derived from it (geometry_of_, witnesses_, rank_, tabled_) are copied;
  // the scene's parts (checker_, scene_, scene_source_, cells_, scene_supports_) are each
  // checker's own.
  // bounds_ comes before checker_, whose inner sets may take its witnesses.
  std::shared_ptr<const RobotBounds> bounds_;
  check::RobotChecker checker_;
  std::vector<const ::fcl::CollisionObjectd*> scene_;
  std::vector<std::size_t> scene_source_;  // check scene object -> index in scene_
  std::vector<std::size_t> geometry_of_;   // checker link -> index in bounds_.geometries()
  // The witnesses the fallback tests: bounds_.witnesses() but those whose points the
  // kernel's inner sets hold (FallbackOptions::kernel_witnesses).
  std::vector<SelfWitness> witnesses_;
  // By geometry pair (a * geometries + b, a < b): the rank of the pair in the order of
  // decide() (FallbackOptions::order).
  std::vector<std::size_t> rank_;
  std::shared_ptr<const Tables> tables_;       // by geometry pair (or null); null: no tables
  std::vector<const PairJointTable*> tabled_;  // tables_first: in the self pairs' order
  // By index in scene_: the cells of an fcl::OcTree, else null; by geometry: the link as
  // OctreeCells takes it (null without a mesh; cell_links_ null while no scene of the
  // checker or its donors has had an octree).
  std::vector<std::unique_ptr<const OctreeCells>> cells_;
  std::shared_ptr<const CellLinks> cell_links_;
  // FallbackOptions::separating_planes (else supports_ null): by geometry, the support of
  // its mesh's vertices (or of its balls), else null; by index in scene_, the object's,
  // else null.
  std::shared_ptr<const Supports> supports_;
  Supports scene_supports_;
};

}  // namespace medspheres::fcl
