#pragma once
// Helpers shared by the distance benchmarks (bench_distance, bench_table2).

#include <memory>

#include <fcl/fcl.h>

#include "bench_percentile.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::bench {

// FCL's exact mesh representation of `mesh`, in the mesh's frame, finished (endModel()).
template <class BV>
std::shared_ptr<::fcl::BVHModel<BV>> make_bvh(const TriangleMesh& mesh) {
  return medspheres::fcl::make_bvh_model<BV>(mesh);
}

}  // namespace medspheres::bench
