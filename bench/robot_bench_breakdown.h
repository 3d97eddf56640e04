#pragma once
// bench_robot --breakdown: where a configuration's time goes, per kind of pair (the scene's
// boxes, its meshes, its octomap; the self pairs). Each method checks every pair of one kind
// at every configuration with no stop at a pair within the margin (the cost of a free
// configuration), timed by the thread's CPU time; the exact method skips pairs whose AABBs
// are farther apart than the margin, as its row does, and poses its parts for each kind.

#include <vector>

#include <fcl/narrowphase/collision_object.h>

#include "robot_bench_exact.h"
#include "robot_bench_scene.h"
#include "robot_bench_spheres.h"

namespace medspheres::bench {

/// Prints, per kind of pair, the pairs per configuration, the pairs within \p margin (by the
/// exact method), and the CPU microseconds per configuration of exact, outer and inner, at
/// the link poses \p poses (RobotBounds::poses).
void print_breakdown(const std::vector<std::vector<::fcl::Transform3d>>& poses,
                     const BenchScene& scene, std::size_t links, std::size_t self_pairs,
                     ExactRobot& exact, const SphereRobot& outer, const SphereRobot& inner,
                     bool self, double margin);

}  // namespace medspheres::bench
