#pragma once
// Helpers shared by the distance benchmarks (bench_distance, bench_table2).

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include <fcl/fcl.h>

#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::bench {

// FCL's exact mesh representation of `mesh`, in the mesh's frame, finished (endModel()).
template <class BV>
std::shared_ptr<::fcl::BVHModel<BV>> make_bvh(const TriangleMesh& mesh) {
  return medspheres::fcl::make_bvh_model<BV>(mesh);
}

// The element of rank round(q (n - 1)) of v sorted ascending (q = 0.5: the median).
// Precondition: v is not empty, 0 <= q <= 1.
inline double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5));
  return v[i];
}

}  // namespace medspheres::bench
