#pragma once
// bench_robot's robot: a URDF's links with their inner and certified outer sphere sets
// (baked with the library's robot bake and cached, or read from a robot file) and their
// exact meshes (FCL BVHModel<OBBRSS>, in the link frames).

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/robot_model.h"
#include "robot_bench_exact.h"

namespace medspheres::bench {

struct RobotSource {
  std::string urdf;
  std::vector<std::string> packages;  ///< PKG=DIR for package://
  std::string robot_file;             ///< a `medspheres robot` output; empty: bake or cache
  std::string cache_dir;              ///< where baked robot files are kept; empty: no cache
  std::size_t spheres_per_link = 0;   ///< bake budget per link
  int jobs = 0;                       ///< links baked at once (0: one per core)
};

struct BenchRobot {
  RobotModel model;  ///< links with inner and outer sets, in link frames
  /// Exact meshes by link name (every link with meshed parts), in the link frame: what
  /// RobotBounds falls back on.
  std::map<std::string, std::shared_ptr<const fcl::MeshModel>> meshes;
  /// Every link's exact geometry: its mesh and its sphere primitives.
  std::map<std::string, ExactLink> exact;
  Solids solids;              ///< of the link meshes
  std::size_t triangles = 0;  ///< of all link meshes
  std::string spheres_from;   ///< where the sets came from, for the report
};

/// Reads the URDF and its meshes, and gets the sets: from source.robot_file when given
/// (its links must be the URDF's), else from the cache, else by baking (then cached).
/// \throws InputError naming the file and the problem.
BenchRobot load_bench_robot(const RobotSource& source);

}  // namespace medspheres::bench
