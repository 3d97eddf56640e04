#pragma once
// The data a kernel sees for one block of kLanes configurations (one per lane): plain
// pointers only, so that the kernel's two builds (scalar, AVX2) share no inline code with
// the rest of the library.
//
// A block is checked in two precisions (robot_checker.h, "precision"): forward kinematics
// and every test in floats, eight lanes at once, each answer three-valued (certain either
// way, or unsure within `slack` of its threshold); then the lanes left unsure again in
// doubles with the documented tests, forward kinematics included, four lanes at a time
// (two halves).

#include <cstdint>

#include "pair_table.h"
#include "robot_layout.h"
#include "scene_grid.h"

namespace medspheres::check::detail {

inline constexpr int kLanes = 8;            // configurations per block: the float lanes
inline constexpr int kHalf = 4;             // the double lanes
inline constexpr int kBoundSlot = kLevels;  // the posed bounding sphere's slot
inline constexpr int kSlots = kLevels + 1;

/// The scene's distance field (distance_field.h), for look-ups inside the kernel (the cell
/// found by a multiplication: a point a rounding away from its cell is still within the
/// pad the bounds carry, or, in floats, within the slack), and outside it the elements'
/// bounding box. field is null when the scene is empty.
template <class T>
struct GridView {
  T origin[3] = {0, 0, 0};
  T side = 0, inverse_side = 0;
  int n[3] = {0, 0, 0};
  const std::uint16_t* field = nullptr;  // DistanceField::bounds(): lower | upper << 8
  T unit = 0;
  T pad = 0;  // SceneGrid::pad(): the bounds' own rounding allowance
  T box_min[3] = {0, 0, 0}, box_max[3] = {0, 0, 0};  // the elements' bounds
};

/// The spheres and bounding spheres of the layout in one precision.
template <class T>
struct KernelSpheres {
  const T *x = nullptr, *y = nullptr, *z = nullptr, *r = nullptr;  // per sphere
  const T* bound = nullptr;  // per link: x, y, z, r in its frame
  /// Per self pair (a, o): the square of T(r_a + r_o + margin + allowance) + slack, in T,
  /// r the links' bounding radii in T (the Block's margin, allowance and slack; slack 0 in
  /// doubles): the pair's bounding spheres may meet where their centres' squared distance
  /// is at most this.
  const T* pair_reach2 = nullptr;
  GridView<T> grid;
};

struct KernelRobot {
  int dof = 0;
  int frames = 0;
  int steps = 0;
  const FrameStep* step = nullptr;
  int links = 0;
  const LinkLayout* link = nullptr;
  int spheres = 0;
  KernelSpheres<double> d;
  KernelSpheres<float> f;
  int pairs = 0;
  const std::uint32_t *pair_a = nullptr, *pair_b = nullptr;
  /// Per link: 1 when no configuration brings it within the margin of the scene
  /// (link_reach.h), so that its scene tests are skipped; null: none is.
  const unsigned char* far = nullptr;
  bool never_near_scene(int l) const { return far && far[l]; }
  /// Per self pair, its joint-space table (pair_table.h; the spheres mode skips the pair
  /// in a lane whose positions fall in a free cell), or none (bits null); null: no tables.
  const PairTableView* table = nullptr;
  int table_slots = 0;  // the positions the tables use (at most kMaxTableSlots)
  const TableSlot* table_slot = nullptr;
  bool fine = false;
  /// The tests in the order they run (the bounds mode: within each level): links + pairs
  /// entries, k < links link k against the scene, else self pair k - links (test_order.h).
  const std::uint32_t* order = nullptr;
  /// The spheres mode runs the links' bounding spheres against the scene after the
  /// order's first `head` tests (0: before every test).
  int head = 0;
  /// The bounds mode's order (within each level): the tests that proved collisions most
  /// often first (RobotChecker::Impl::learn_order).
  const std::uint32_t* bounds_order = nullptr;
};

/// One pass over a block's lanes in one precision: W lanes of T, the frames posed, a
/// workspace for the posed spheres.
template <class T>
struct Pass {
  const T* frames = nullptr;            // frames * 12 * W: X_WF rows of R, then p
  T* posed = nullptr;                   // per sphere 3 * W, then per link 3 * W (bounding spheres)
  unsigned char* posed_flag = nullptr;  // links * kSlots
  unsigned char* near = nullptr;        // per sphere: lanes its field look-up left open
  int* lists = nullptr;                 // per link (spheres mode)
  unsigned char* pending = nullptr;     // per link and self pair (bounds mode)
  unsigned char* unsure = nullptr;      // per link and self pair (bounds mode, floats)
  unsigned lanes = 0;                   // the lanes that hold a configuration (bits)
  T slack = 0;                          // 0 in doubles
};

struct Block;
/// Called (bounds mode) for a pair left undecided in a lane: by the double pass (lane of
/// the half block.half), and by the float pass for its lanes whose every test was certain
/// (lane of kLanes, block.half -1); scene pairs with other = -1 (the callee finds the
/// objects near the posed spheres: in floats, within the slack more).
using UndecidedSink = void (*)(Block& block, int lane, int link, int other);

struct Block {
  // Input.
  const double* q = nullptr;  // dof * kLanes: q[j * kLanes + lane]
  unsigned lanes = 0;         // the lanes that hold a configuration (bits)
  bool bounds = false;        // false: spheres only
  bool self = true;
  bool floats = true;  // false: every test in doubles
  // Spheres mode, an edge's block: the tests stop at the first lane found colliding, so
  // `colliding` is not empty exactly when some lane collides (which lanes then means
  // nothing more); a block with no colliding lane has every lane's verdict as without.
  bool any = false;
  // Learning: per test (KernelRobot::order's indices), the lanes it finds colliding (the
  // bounds mode: proves colliding, at either level) are counted here, and every test runs
  // in every lane (no verdict then).
  std::uint32_t* hits = nullptr;
  // Bounds mode, > 0: a probe. Only the bounds order's tests [probe_from, probe) run, at
  // the planner's level, and the float pass's unsure lanes are not checked again:
  // `colliding` holds lanes proved colliding (the verdict of the whole run too), every
  // other lane is open (`undecided` means nothing then).
  int probe = 0, probe_from = 0;
  double margin = 0.0, allowance = 0.0;
  float slack = 0.0f;  // m: the float tests' allowance (robot_checker.cpp)
  // Workspace, sized by the caller.
  double* frames = nullptr;             // two halves of frames * 12 * kHalf
  float* frames_f = nullptr;            // frames * 12 * kLanes
  double* posed = nullptr;              // (spheres + links) * 3 * kHalf
  float* posed_f = nullptr;             // (spheres + links) * 3 * kLanes
  unsigned char* posed_flag = nullptr;  // links * kSlots
  unsigned char* near = nullptr;        // spheres
  int* lists = nullptr;                 // links
  unsigned char* pending = nullptr;     // links + self pairs
  unsigned char* unsure = nullptr;      // links + self pairs
  // Output (lane bits).
  unsigned colliding = 0, undecided = 0;
  unsigned rechecked = 0;  // the lanes the floats left unsure (checked again in doubles)
  UndecidedSink sink = nullptr;
  void* context = nullptr;  // the sink's
  int half = 0;  // the half the double pass is in (for the sink's lane); -1: the float pass
};

using KernelFn = void (*)(const KernelRobot& robot, const SceneGrid& scene, Block& block);

void run_block_scalar(const KernelRobot& robot, const SceneGrid& scene, Block& block);
/// Present only when the library was built for x86-64 (kernel_avx2.cpp).
void run_block_avx2(const KernelRobot& robot, const SceneGrid& scene, Block& block);

/// Blocks checked together in the spheres mode, their set tests compacted: the bounding
/// tests of every block first, then each test's sets in groups of kLanes (configuration,
/// test) items gathered across the blocks (their frames copied into one pass's lanes),
/// then the double pass of each block's unsure lanes. Each lane's verdict is that of
/// run_block (every test runs in each lane not found colliding, with the same operations).
/// The blocks share their workspace but frames_f: each its own (frame 0 W). Not for
/// learning (hits) or the bounds mode.
struct Batch {
  Block* blocks = nullptr;
  int count = 0;
  float* frames_f = nullptr;      // the gathered lanes' frames: frames * 12 * kLanes
  unsigned char* need = nullptr;  // count * (links + self pairs): lanes left to test
  unsigned* unsure = nullptr;     // count
};

using BatchFn = void (*)(const KernelRobot& robot, const SceneGrid& scene, Batch& batch);

void run_batch_scalar(const KernelRobot& robot, const SceneGrid& scene, Batch& batch);
/// Present only when the library was built for x86-64 (kernel_avx2.cpp).
void run_batch_avx2(const KernelRobot& robot, const SceneGrid& scene, Batch& batch);

}  // namespace medspheres::check::detail
