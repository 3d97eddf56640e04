#pragma once
// SphereGroups: a level between a link's bounding sphere and its set. The set's spheres
// are split into a few groups of neighbours (by their centres' order along the axis of
// their largest spread), each with a ball that holds every sphere of its group with room:
// |c_i - centre| + r_i + room <= radius, room = 1e-9 (1 + extent), far more than the
// rounding of posing a point in doubles. A ball farther than its radius plus a threshold
// from the scene keeps every sphere of its group farther than its own radius plus that
// threshold, so the kernel skips their look-ups (no answer changes). Frame: the link's.

#include <cstdint>

namespace medspheres::check::detail {

inline constexpr int kMaxGroups = 4;

struct SphereGroups {
  int count = 0;                        // 0: no groups (too few spheres, or more than 32)
  std::uint32_t mask[kMaxGroups] = {};  // bit i: sphere i of the set (a partition)
  double ball[kMaxGroups][4] = {};      // x, y, z, r
};

/// Splits the n spheres (x, y, z, r)[i] into \p groups groups (1 <= groups <=
/// kMaxGroups) of consecutive ranks along the axis of the centres' largest spread;
/// none (count 0) when n < 2 groups or n > 32. \p extent: at least every |coordinate|
/// plus radius (the room's scale).
SphereGroups group_spheres(const double* x, const double* y, const double* z, const double* r,
                           int n, int groups, double extent);

}  // namespace medspheres::check::detail
