#pragma once
// What bench_robot and bench_checker set up alike: the self pairs left out (an SRDF's, and
// those within the margin at the default configuration, as MoveIt's setup assistant does
// with its "Default" reason), and a generated robot's files.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "bench_args.h"
#include "robot_bench_robot.h"

namespace medspheres::bench {

using NamePairs = std::vector<std::pair<std::string, std::string>>;

/// The options bench_robot and bench_checker share. Defaults: the G1 of /work/shared and
/// its meshes when present, bakes cached under $XDG_CACHE_HOME (else ~/.cache)
/// /medspheres/bench_robot.
struct RobotBenchOptions {
  RobotSource robot;
  std::string generated;  // a generated robot's name ("coarse-arm"); empty: the URDF
  std::size_t configs = 10000;
  unsigned seed = 1;
  double margin = 0.01;
  std::string srdf;
  std::string meshes;
  bool self = true;

  RobotBenchOptions();
  /// The URDF (positional), --robot, --configs, --seed, --margin, --cache, --jobs,
  /// --package, --srdf, the meshes and --no-self.
  void add_to(Args& args);
};

/// The pairs excluded from self-collision: those of \p srdf (none when empty), and those
/// within \p margin at the default configuration (every joint at 0, clamped to its limits)
/// by the exact meshes; \p by_default receives how many of the latter.
NamePairs disabled_pairs(const std::string& srdf, double margin, const BenchRobot& robot,
                         std::size_t& by_default);

/// A generated robot's files (\p name "coarse-arm": tests/support/coarse_arm.h), in
/// \p cache_dir (the same bytes each time, so the bake's cache key holds), or in a
/// temporary folder removed with this object when \p cache_dir is empty. An empty name
/// writes nothing.
class GeneratedRobot {
 public:
  GeneratedRobot(const std::string& name, const std::string& cache_dir);
  ~GeneratedRobot();
  GeneratedRobot(const GeneratedRobot&) = delete;
  GeneratedRobot& operator=(const GeneratedRobot&) = delete;

  /// The URDF written (empty for an empty name).
  const std::string& urdf() const noexcept { return urdf_; }

 private:
  std::filesystem::path temp_;
  std::string urdf_;
};

/// What main() of bench_robot and bench_checker does around their run: \p urdf replaced by
/// the robot \p generated names (GeneratedRobot, in \p cache_dir) when it names one, then
/// \p run; 2 with a message naming \p bench for a missing robot file or an InputError, 1
/// with the message of any other exception (a figure the bench checks came out wrong), else
/// what \p run returns.
int run_robot_bench(const char* bench, const std::string& generated, const std::string& cache_dir,
                    std::string& urdf, const std::function<int()>& run);

}  // namespace medspheres::bench
