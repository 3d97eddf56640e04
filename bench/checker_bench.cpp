// The robot checker alone (docs/checker.md): bench_robot's checker table without its
// first one, for a quicker run and for other sphere budgets. The robot, the scene, the
// configurations, the self pairs and the reference are bench_robot's (robot_bench.cpp's
// header): the reference is FCL's exact mesh query per configuration (the octomap as one
// mesh of its cells' boxes), "vs exact" divides the time of FCL's exact query on the
// scene's octree (bench_robot's `exact` row, here timed in one pass) by a row's.
//
// The levels: the planner's sets baked with --planner-spheres per link, the fine sets
// with --fine-spheres per link, and with --tree-spheres the certified fallback's sphere
// trees (all cached as bench_robot's bakes are).
//
// Usage: bench_checker [URDF | --robot coarse-arm] [--configs N] [--seed S] [--margin M]
//                      [--planner-spheres K] [--fine-spheres K] [--tree-spheres K] [--order-samples
//                      N]
//                      [--cache DIR]
//                      [--srdf F]
//                      [--fallback-report] ...
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_timing.h"
#include "medspheres/fcl/robot_bounds.h"
#include "robot_bench_check.h"
#include "robot_bench_exact.h"
#include "robot_bench_fallback.h"
#include "robot_bench_robot.h"
#include "robot_bench_scene.h"
#include "robot_bench_setup.h"

namespace {

namespace mb = medspheres::bench;
namespace mf = medspheres::fcl;

struct Options : mb::RobotBenchOptions {
  std::size_t planner_spheres = 8;
  std::size_t fine_spheres = 32;
  std::size_t tree_spheres = 0;
  std::size_t order_samples = 0;
  std::size_t table_cells = 0;
  std::size_t max_cells = medspheres::check::CheckerOptions{}.max_cells;
  std::size_t table_pairs = 0;
  std::string table_store;
  double edge_length = 0.5;
  double resolution = 0.02;
  bool fcl_loop = true;
  bool all_cores = true;
  int repeats = 3;
  int spheres_repeats = 0;
  bool fallback_report = false;
};

Options parse(int argc, char** argv) {
  Options o;
  mb::Args args("bench_checker", "The robot checker against exact meshes");
  CLI::App& app = args.app();
  o.add_to(args);
  args.add("--planner-spheres", o.planner_spheres, "The planner's level: spheres per link");
  args.add("--fine-spheres", o.fine_spheres, "The fine level: spheres per link");
  args.add("--tree-spheres", o.tree_spheres,
           "The certified fallback's sphere trees: spheres per link (0: the fine sets)");
  args.add("--order-samples", o.order_samples,
           "The certified fallback's pair order and witnesses, learnt from this many "
           "configurations (0: none)");
  args.add("--max-cells", o.max_cells, "The checkers' scene grid: cells at most");
  args.add("--table-cells", o.table_cells,
           "The certified fallback's joint-space tables of self pairs: cells per pair (0: none)");
  args.add("--table-pairs", o.table_pairs,
           "With --table-cells: tables for this many self pairs only, those seen colliding most "
           "often first (0: every pair that takes one)");
  args.add("--table-store", o.table_store,
           "With --table-cells: a folder that keeps the tables, read instead of baked when it "
           "holds them ('': baked every run)");
  args.add("--edge-length", o.edge_length, "Edges: joint-space length");
  args.add("--resolution", o.resolution, "Edges: resolution");
  args.add("--repeats", o.repeats, "Each time the best of this many runs");
  args.add("--spheres-repeats", o.spheres_repeats,
           "check/s on one thread: the best of this many runs (0: --repeats; for a profile)");
  app.add_flag("!--no-fcl-loop", o.fcl_loop, "Leave out the loop of FCL calls");
  app.add_flag("!--one-thread", o.all_cores, "Leave out the rows on every core");
  app.add_flag("--fallback-report", o.fallback_report,
               "Instead of the table: where the certified checker's fallback goes, pair by pair");
  args.parse(argc, argv);
  return o;
}

int run(const Options& o) {
  mb::RobotSource source = o.robot;
  source.spheres_per_link = o.fine_spheres;
  const mb::BenchRobot fine = mb::load_bench_robot(source);
  source.spheres_per_link = o.planner_spheres;
  const mb::BenchRobot planner =
      o.planner_spheres == o.fine_spheres ? fine : mb::load_bench_robot(source);
  source.spheres_per_link = o.tree_spheres;
  const mb::BenchRobot trees = o.tree_spheres > 0 ? mb::load_bench_robot(source) : mb::BenchRobot{};
  const mb::BenchScene scene = mb::make_scene(o.seed, o.meshes, 1.0);
  const std::vector<const ::fcl::CollisionObjectd*> objects = scene.pointers();
  std::size_t by_default = 0;
  const mb::NamePairs disabled = mb::disabled_pairs(o.srdf, o.margin, fine, by_default);
  const mf::RobotBounds robot(fine.model, fine.meshes, disabled);
  mb::ExactRobot exact(robot, fine.exact, objects);
  mb::Solids solids = fine.solids;
  solids.insert(scene.solids.begin(), scene.solids.end());
  mb::ExactRobot exact_reference(robot, fine.exact, scene.pointers(true), solids);
  const auto configs = mf::sample_configurations(fine.model, robot.kinematics(), o.configs, o.seed);
  std::printf(
      "robot %s: %zu links with geometry, %zu self pairs (%zu within the margin at the "
      "default configuration excluded), %zu triangles\n",
      o.robot.urdf.c_str(), robot.geometries().size(), robot.self_pairs().size(), by_default,
      fine.triangles);
  std::printf("planner sets: %s\nfine sets: %s\n", planner.spheres_from.c_str(),
              fine.spheres_from.c_str());
  if (o.tree_spheres > 0) std::printf("tree sets: %s\n", trees.spheres_from.c_str());
  mb::CheckerBenchInput in;
  in.planner = &planner;
  in.fine = &fine;
  in.trees = o.tree_spheres > 0 ? &trees : nullptr;
  in.order_samples = o.order_samples;
  in.order_seed = o.seed + 1;
  in.table_cells = o.table_cells;
  in.table_pairs = o.table_pairs;
  in.table_store = o.table_store;
  in.max_cells = o.max_cells;
  in.scene = objects;
  in.disabled = disabled;
  in.configs = configs;
  in.margin = o.margin;
  in.self = o.self;
  in.edge_length = o.edge_length;
  in.resolution = o.resolution;
  in.repeats = o.repeats;
  in.spheres_repeats = o.spheres_repeats;
  in.fcl_loop = o.fcl_loop;
  in.all_cores = o.all_cores;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const auto t0 = mb::Clock::now();
  for (const Eigen::VectorXd& q : configs)
    in.reference.push_back(exact_reference.collide(robot.poses(q, I), o.self, o.margin));
  const double reference_seconds = mb::seconds_since(t0);
  std::size_t colliding = 0;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const double t = mb::thread_cpu_micros();
    colliding += exact.collide(robot.poses(configs[i], I), o.self, o.margin);
    in.exact_micros += (mb::thread_cpu_micros() - t) / static_cast<double>(configs.size());
  }
  std::size_t truth = 0;
  for (char c : in.reference) truth += c;
  std::printf(
      "%zu configurations (seed %u), margin %.4g m; reference: %zu within the margin (%.1f s); "
      "exact (FCL, meshes and octree): %zu, %.1f us per configuration\n",
      configs.size(), o.seed, o.margin, truth, reference_seconds, colliding, in.exact_micros);
  if (o.fallback_report) {
    medspheres::check::CheckerOptions co;
    co.margin = in.margin;
    co.disabled = in.disabled;
    co.self = in.self;
    mf::FallbackOptions fallback;
    fallback.trees = in.trees ? &trees.model : nullptr;
    fallback.order.samples = o.order_samples;
    fallback.order.margin = o.margin;
    fallback.order.seed = o.seed + 1;
    fallback.table_cells = o.table_cells;
    fallback.table_pairs = o.table_pairs;
    fallback.table_store = o.table_store;
    const mf::CertifiedChecker certified(
        planner.model, o.planner_spheres == o.fine_spheres ? nullptr : &fine.model, fine.meshes,
        objects, co, fallback);
    mb::print_fallback_report(in, certified);
    return 0;
  }
  mb::print_checker_rows(in);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  mb::restart_with_passive_openmp(argv);
  Options o = parse(argc, argv);
  return mb::run_robot_bench("bench_checker", o.generated, o.robot.cache_dir, o.robot.urdf,
                             [&o] { return run(o); });
}
