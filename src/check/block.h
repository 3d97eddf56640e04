#pragma once
// The data a kernel sees for one block of four configurations (one per lane): plain
// pointers only, so that the kernel's two builds (scalar, AVX2) share no inline code with
// the rest of the library.

#include <cstdint>

#include "robot_layout.h"
#include "scene_grid.h"

namespace medspheres::check::detail {

inline constexpr int kLanes = 4;
inline constexpr int kBoundSlot = kLevels;  // the posed bounding sphere's slot
inline constexpr int kSlots = kLevels + 1;

/// The scene grid's lower bounds, for look-ups inside the kernel (SceneGrid::clear's, with
/// the cell found by a multiplication: a point a rounding away from its cell is still
/// within the pad the bounds carry). lower is null when the scene is empty.
struct GridView {
  double origin[3] = {0, 0, 0};
  double inverse_side = 0.0;
  long n[3] = {0, 0, 0};
  const std::uint8_t* lower = nullptr;  // in units of `unit`
  double unit = 0.0;
};

struct KernelRobot {
  int frames = 0;
  int steps = 0;
  const FrameStep* step = nullptr;
  int links = 0;
  const LinkLayout* link = nullptr;
  int spheres = 0;
  const double *x = nullptr, *y = nullptr, *z = nullptr, *r = nullptr;
  int pairs = 0;
  const std::uint32_t *pair_a = nullptr, *pair_b = nullptr;
  bool fine = false;
  GridView grid;
};

struct Block;
/// Called by the kernel (bounds mode) for a pair left undecided in a lane: scene pairs
/// with other = -1 (the callee finds the objects near the posed spheres).
using UndecidedSink = void (*)(Block& block, int lane, int link, int other);

struct Block {
  // Input.
  const double* q = nullptr;  // dof * kLanes: q[j * kLanes + lane]
  unsigned lanes = 0;         // the lanes that hold a configuration (bits)
  bool bounds = false;        // false: spheres only
  bool self = true;
  double margin = 0.0, allowance = 0.0;
  // Workspace, sized by the caller.
  double* frames = nullptr;             // frames * 12 * kLanes (frame 0: identity)
  double* posed = nullptr;              // per sphere 3 * kLanes, then per link 3 * kLanes
  unsigned char* posed_flag = nullptr;  // links * kSlots
  unsigned char* pending = nullptr;     // links + self pairs (bounds mode)
  // Output (lane bits).
  unsigned colliding = 0, undecided = 0;
  UndecidedSink sink = nullptr;
  void* context = nullptr;  // the sink's
};

using KernelFn = void (*)(const KernelRobot& robot, const SceneGrid& scene, Block& block);

void run_block_scalar(const KernelRobot& robot, const SceneGrid& scene, Block& block);
/// Present only when the library was built for x86-64 (kernel_avx2.cpp).
void run_block_avx2(const KernelRobot& robot, const SceneGrid& scene, Block& block);

}  // namespace medspheres::check::detail
