#pragma once
// bench_robot's rows for the batched robot checker (medspheres/check/robot_checker.h and
// medspheres/fcl/certified_checker.h): spheres only and certified, per configuration and
// per edge, on one thread and on every core, and the same sphere checks written as a loop
// of FCL calls, each with the reference's missed collisions and false alarms.

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <fcl/narrowphase/collision_object.h>
#include <Eigen/Core>

#include "medspheres/check/robot_checker.h"
#include "robot_bench_robot.h"

namespace medspheres::bench {

struct CheckerBenchInput {
  const BenchRobot* planner = nullptr;  ///< the planner's sets (K per link)
  const BenchRobot* fine = nullptr;     ///< the fine sets, with the meshes (may equal planner)
  /// The certified fallback's sphere trees (CertifiedChecker's `trees`); null: the fine sets.
  const BenchRobot* trees = nullptr;
  /// The fallback's learnt pair order and witnesses (FallbackOptions::order.samples).
  std::size_t order_samples = 0;
  /// Their seed (FallbackOptions::order.seed): not the configurations' own, so that the
  /// witnesses are not learnt on the configurations they are timed on.
  unsigned order_seed = 2;
  /// The fallback's joint-space tables of self pairs (FallbackOptions::table_cells).
  std::size_t table_cells = 0;
  /// The pairs that get one (FallbackOptions::table_pairs).
  std::size_t table_pairs = 0;
  /// Their store (FallbackOptions::table_store); empty: none.
  std::string table_store;
  /// The checkers' scene grid: cells at most (CheckerOptions::max_cells).
  std::size_t max_cells = check::CheckerOptions{}.max_cells;
  std::vector<const ::fcl::CollisionObjectd*> scene;
  std::vector<std::pair<std::string, std::string>> disabled;
  std::vector<Eigen::VectorXd> configs;
  std::vector<char> reference;  ///< per configuration: colliding by the exact meshes
  double margin = 0.0;
  bool self = true;
  double exact_micros = 0.0;  ///< the exact method's time per configuration, for ratios
  double edge_length = 0.5;   ///< joint-space length of the edges (rad, m)
  double resolution = 0.02;   ///< of the edges
  int repeats = 3;            ///< each timing the best of this many runs
  int spheres_repeats = 0;    ///< check/s on one thread: the best of this many (0: repeats)
  bool fcl_loop = true;       ///< the row of FCL calls on the same spheres
  bool all_cores = true;      ///< the rows on every core besides those on one thread
};

/// Prints the checker's table.
void print_checker_rows(const CheckerBenchInput& in);

}  // namespace medspheres::bench
