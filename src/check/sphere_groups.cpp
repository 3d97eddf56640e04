#include "sphere_groups.h"

#include <algorithm>
#include <numeric>
#include <vector>

#include "medspheres/min_enclosing_ball.h"
#include "medspheres/sphere_set.h"

namespace medspheres::check::detail {

SphereGroups group_spheres(const double* x, const double* y, const double* z, const double* r,
                           int n, int groups, double extent) {
  SphereGroups out;
  groups = std::clamp(groups, 1, kMaxGroups);
  if (n < 2 * groups || n > 32) return out;
  const double* c[3] = {x, y, z};
  int axis = 0;
  double spread = -1.0;
  for (int k = 0; k < 3; ++k) {
    const auto [lo, hi] = std::minmax_element(c[k], c[k] + n);
    if (*hi - *lo > spread) spread = *hi - *lo, axis = k;
  }
  std::vector<int> rank(static_cast<std::size_t>(n));
  std::iota(rank.begin(), rank.end(), 0);
  std::stable_sort(rank.begin(), rank.end(), [&](int a, int b) { return c[axis][a] < c[axis][b]; });
  const double room = 1e-9 * (1.0 + extent);
  out.count = groups;
  for (int g = 0; g < groups; ++g) {
    std::vector<Sphere> members;
    for (int i = g * n / groups; i < (g + 1) * n / groups; ++i) {
      const int s = rank[static_cast<std::size_t>(i)];
      out.mask[g] |= 1u << s;
      members.push_back({Eigen::Vector3d(x[s], y[s], z[s]), r[s]});
    }
    const Sphere b = min_enclosing_ball(members);
    double radius = 0.0;  // recomputed from the centre, so that the room is on top of it
    for (const Sphere& m : members)
      radius = std::max(radius, (m.center - b.center).norm() + m.radius);
    for (int k = 0; k < 3; ++k) out.ball[g][k] = b.center[k];
    out.ball[g][3] = radius + room;
  }
  return out;
}

}  // namespace medspheres::check::detail
