// Certified queries for a whole robot against a scene and itself
// (docs/certified-queries.md): the robot at seeded joint configurations within its limits,
// each checked for collision within a margin (1 cm by default) by six methods in one run:
//   exact    FCL's exact mesh distance (BVHModel<OBBRSS> per link), pair by pair, stopping
//            at the first pair within the margin;
//   exact+   the same with robot_collide's robot-level tricks: its self-pair order
//            (SelfPairOrder, without witnesses, which are sphere pairs) and its scene
//            skip (fcl::balls_near);
//   outer    the certified covering sets alone (medspheres::fcl::distance on
//            SphereSetGeometry, the margin preset as min_distance);
//   inner    the inner sets alone, the same way;
//   bounds   both sets at once with the exact meshes as fallback
//            (medspheres::fcl::robot_collide), the library's certified query, its self
//            pairs ordered, and its witness sphere pairs picked, by --order-samples
//            seeded configurations (seed + 1); a verdict left undecided (no mesh pair to
//            settle a pair) counts as colliding;
//   bounds/g the same with the self pairs in geometry order and no witnesses.
// The samples are configurations of their own: none of them is one of the timed ones.
// Every method visits the same pairs (the links against every scene object, and the
// self-collision pairs of RobotBounds); exact skips the pairs whose world AABBs are
// farther apart than the margin (a broadphase that never changes its answer). exact and
// bounds visit the self pairs first, outer and inner the scene first. The methods run in
// blocks of configurations, in turn, each call timed by the thread's CPU time.
//
// Reference: the smallest exact distance over all pairs (FCL mesh distance, negative
// answers clamped to 0; the octomap as one mesh of its occupied cells' boxes, so that the
// reference does not rest on FCL's octree code), untimed; a configuration collides when
// it is <= the margin. The exact methods' verdicts are checked against it.
// Missed collisions: the reference collides and the method says free; false alarms: the
// other way round. Distance error: of the smallest distance over the pairs, against the
// reference: outer sets (the lower bound), inner sets (the upper bound), and for the
// bounds the larger of (reference - lower) and (upper - reference); "bound violations"
// counts configurations whose reference lies outside [lower, upper] (expected 0).
//
// Self-collision pairs exclude adjacent links, the pairs of --srdf, and (as MoveIt's
// setup assistant does with its "Default" reason) the pairs within the margin at the
// default configuration (every joint at 0, clamped to its limits).
//
// The sets: the library's robot bake (inner and certified outer set per link, the robot
// command's defaults, --spheres-per-link each) at startup, cached in --cache under the
// batch cache's key (batch_robot.h: the URDF's and its meshes' bytes, the options, the
// library's version, not the commit: after a change to the bake between releases, pass
// --cache ''); or --robot-file from `medspheres robot`.
//
// Then the robot checker's table (robot_bench_check.h; --no-checker leaves it out): the
// planner level baked with --planner-spheres K per link (cached as above), the sets above as
// its fine level; spheres only, the bounds alone, and certified (with the meshes' fallback),
// per configuration and per edge (--edge-length, --resolution), on one thread (its CPU
// time) and on every core (wall clock), each the best of three runs; and a loop of FCL calls
// on the same spheres. Missed and alarms against the same reference.
//
// The robot: a URDF (the G1 of ../shared by default), or with --robot coarse-arm the
// generated 7-joint arm of coarse meshes (tests/support/coarse_arm.h: 11 links of 32 to 256
// triangles), written into the cache folder (a temporary one with --cache '').
//
// --breakdown N: after the table, where the time goes per kind of pair (boxes, meshes,
// octomap, self) over the first N configurations, every pair with no stop
// (robot_bench_breakdown.h).
//
// Usage: bench_robot [URDF | --robot coarse-arm] [--configs N] [--seed S] [--margin M]
//                    [--robot-file F] [--cache DIR] [--spheres-per-link K] [--srdf F]
//                    [--meshes DIR] [--breakdown N] [--planner-spheres K] [--no-checker] ...
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <fcl/fcl.h>

#include "bench_args.h"
#include "bench_timing.h"
#include "medspheres/error.h"
#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/fcl/sphere_set_geometry.h"
#include "robot_bench_breakdown.h"
#include "robot_bench_check.h"
#include "robot_bench_exact.h"
#include "robot_bench_robot.h"
#include "robot_bench_scene.h"
#include "robot_bench_setup.h"
#include "robot_bench_spheres.h"

namespace {

namespace mf = medspheres::fcl;
namespace mb = medspheres::bench;
using Poses = std::vector<::fcl::Transform3d>;
using mb::Clock;

struct Options : mb::RobotBenchOptions {
  double scale = 1.0;
  std::size_t distance_every = 10;
  bool explain = false;
  std::size_t breakdown = 0;
  std::size_t order_samples = 4000;
  std::size_t planner_spheres = 8;  // the checker's planner level (the bake's sets: its fine level)
  double edge_length = 0.5;
  double resolution = 0.02;
  bool checker = true;
};

Options parse(int argc, char** argv) {
  Options o;
  o.robot.spheres_per_link = 32;
  mb::Args args("bench_robot", "Certified robot queries against exact meshes");
  CLI::App& app = args.app();
  o.add_to(args);
  args.add("--scale", o.scale, "Scale of the scene's positions and sizes");
  args.add("--robot-file", o.robot.robot_file, "Sets from `medspheres robot` (no bake)");
  args.add("--spheres-per-link", o.robot.spheres_per_link, "Bake budget per link");
  args.add("--distance-every", o.distance_every, "Distance errors on every k-th configuration");
  args.add("--order-samples", o.order_samples,
           "Seeded configurations that order the self pairs and pick witnesses (SelfPairOrder; 0: "
           "geometry order, none)");
  app.add_flag("--explain", o.explain, "Print the pairs of configurations whose bounds fail");
  args.add("--breakdown", o.breakdown,
           "Time per kind of pair (boxes, meshes, octomap, self) over the first N "
           "configurations, no stop (0: none)");
  args.add("--planner-spheres", o.planner_spheres,
           "The checker's planner level: spheres per link (the sets above are its fine level)");
  args.add("--edge-length", o.edge_length, "The checker's edges: joint-space length");
  args.add("--resolution", o.resolution, "The checker's edges: resolution");
  app.add_flag("!--no-checker", o.checker, "Leave out the robot checker's rows");
  args.parse(argc, argv);
  return o;
}

// CPU time of the thread per configuration for the link poses alone, the same calls every
// method makes.
double kinematics_micros(const mf::RobotBounds& robot,
                         const std::vector<Eigen::VectorXd>& configs) {
  const double t0 = mb::thread_cpu_micros();
  double sink = 0.0;
  for (const Eigen::VectorXd& q : configs)
    sink += robot.poses(q, Eigen::Isometry3d::Identity()).back().translation().x();
  const double micros = mb::thread_cpu_micros() - t0;
  if (!std::isfinite(sink)) std::printf("(a pose is not finite)\n");
  return micros / static_cast<double>(std::max<std::size_t>(configs.size(), 1));
}

// What one method said about every configuration.
struct MethodRun {
  std::string name;
  double micros = 0.0;          // CPU time of the thread per configuration
  std::vector<char> colliding;  // per configuration
  std::size_t mesh_free = 0;    // configurations decided without a mesh query
  std::size_t undecided = 0;    // configurations left undecided (counted as colliding)
  std::size_t by_witness = 0;   // configurations decided by a witness pair (RobotBounds)
  double mesh_micros = 0.0;     // total CPU time of the configurations that queried a mesh
  bool uses_mesh = false;
  bool queried_mesh = false;  // by the last configuration
};

// A method: its verdict on configuration i (colliding), noting in r what it used.
using Method = std::function<bool(std::size_t i, MethodRun& r)>;

// Every method on every configuration, in blocks of kBlock configurations: each method
// runs a block in turn (starting one further each block), so that the load of a shared
// machine falls on all of them alike while each keeps its data warm within a block; each
// call timed by the thread's CPU time.
constexpr std::size_t kBlock = 250;

std::vector<MethodRun> run_methods(const std::vector<std::pair<std::string, Method>>& methods,
                                   std::size_t n) {
  std::vector<MethodRun> runs(methods.size());
  for (std::size_t m = 0; m < methods.size(); ++m) {
    runs[m].name = methods[m].first;
    runs[m].colliding.resize(n);
  }
  for (std::size_t begin = 0, block = 0; begin < n; begin += kBlock, ++block)
    for (std::size_t k = 0; k < methods.size(); ++k) {
      const std::size_t m = (block + k) % methods.size();
      MethodRun& r = runs[m];
      for (std::size_t i = begin; i < std::min(n, begin + kBlock); ++i) {
        r.queried_mesh = false;
        const double t0 = mb::thread_cpu_micros();
        r.colliding[i] = methods[m].second(i, r);
        const double dt = mb::thread_cpu_micros() - t0;
        r.micros += dt / static_cast<double>(n);
        if (r.queried_mesh) r.mesh_micros += dt;
      }
    }
  return runs;
}

// The exact reference (untimed): every configuration's verdict, and on every k-th one the
// smallest exact distance and the sphere bounds' minimum.
struct Reference {
  std::vector<char> colliding;
  std::vector<std::size_t> sampled;
  std::vector<double> exact, lower, upper;  // per sampled configuration
};

Reference reference(const mf::RobotBounds& robot, mb::ExactRobot& exact,
                    const std::vector<Eigen::VectorXd>& configs,
                    const std::vector<const ::fcl::CollisionObjectd*>& scene, bool self,
                    double margin, std::size_t every) {
  Reference r;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const Poses X = robot.poses(configs[i], I);
    r.colliding.push_back(exact.collide(X, self, margin));
    if (i % every != 0) continue;
    r.sampled.push_back(i);
    r.exact.push_back(exact.distance(X, self));
    const mf::RobotBoundsResult b = mf::robot_bounds(robot, configs[i], scene, self);
    r.lower.push_back(b.minimum.lower);
    r.upper.push_back(b.minimum.upper);
  }
  return r;
}

// Every pair of a configuration whose bounds do not hold the pair's exact distance.
void explain(const mf::RobotBounds& robot, mb::ExactRobot& exact, const Eigen::VectorXd& q,
             const std::vector<const ::fcl::CollisionObjectd*>& scene, bool self) {
  const Poses X = robot.poses(q, Eigen::Isometry3d::Identity());
  for (const mf::LinkPairBounds& p : mf::robot_bounds(robot, q, scene, self, true).pairs) {
    const double d = exact.pair(X, p.link, p.other, p.self);
    if (d >= p.bounds.lower && d <= p.bounds.upper) continue;
    std::printf("  %s vs %s %zu: exact %.9g, bounds [%.9g, %.9g]\n",
                robot.geometries()[p.link].link().c_str(), p.self ? "link" : "scene object",
                p.other, d, p.bounds.lower, p.bounds.upper);
  }
}

// The exact reference's own rounding: FCL's distance between two meshes that share a
// vertex comes out as a few ulps (even a subnormal such as 2e-319) rather than 0.
constexpr double kOracleRounding = 1e-12;

struct ErrorStats {
  double mean = 0.0, max = 0.0;
  std::size_t violations = 0;
};

// err(i): the method's distance error at configuration i (>= 0 when the bound holds).
template <class F>
ErrorStats error_stats(std::size_t n, F&& err) {
  ErrorStats s;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = err(i);
    if (e < -kOracleRounding) ++s.violations;
    s.mean += std::abs(e) / static_cast<double>(n);
    s.max = std::max(s.max, std::abs(e));
  }
  return s;
}

void print_row(const MethodRun& m, const Reference& ref, double exact_micros, const ErrorStats& e) {
  std::size_t colliding = 0, missed = 0, alarms = 0;
  for (std::size_t i = 0; i < m.colliding.size(); ++i) {
    const bool truth = ref.colliding[i];
    colliding += m.colliding[i] ? 1 : 0;
    if (truth && !m.colliding[i]) ++missed;
    if (!truth && m.colliding[i]) ++alarms;
  }
  const double n = static_cast<double>(m.colliding.size());
  char decided[32] = "-";
  if (m.uses_mesh) std::snprintf(decided, sizeof decided, "%.2f%%", 100.0 * m.mesh_free / n);
  std::printf("%-8s %12.1f %8.1fx %10s %10zu %8zu %8zu %10.2f %10.2f %6zu\n", m.name.c_str(),
              m.micros, exact_micros / m.micros, decided, colliding, missed, alarms, 1e3 * e.mean,
              1e3 * e.max, e.violations);
}

}  // namespace

namespace {

// Every pair of a configuration that is within the margin by the reference, with the
// verdict of its sphere bounds.
void explain_near(const mf::RobotBounds& robot, mb::ExactRobot& exact, const Eigen::VectorXd& q,
                  const std::vector<const ::fcl::CollisionObjectd*>& scene, bool self,
                  double margin) {
  const Poses X = robot.poses(q, Eigen::Isometry3d::Identity());
  const auto& g = robot.geometries();
  for (const mf::LinkPairBounds& p : mf::robot_bounds(robot, q, scene, self, true).pairs) {
    const double d = exact.pair(X, p.link, p.other, p.self);
    if (d > margin) continue;
    const mf::CollideResult c =
        p.self ? mf::decide(g[p.link], X[p.link], g[p.other], X[p.other], margin)
               : mf::decide(g[p.link], X[p.link], *scene[p.other]->collisionGeometry(),
                            scene[p.other]->getTransform(), margin);
    std::printf("  %s vs %s %zu: exact %.9g, bounds [%.9g, %.9g], decided %d\n",
                g[p.link].link().c_str(), p.self ? g[p.other].link().c_str() : "scene object",
                p.other, d, p.bounds.lower, p.bounds.upper, static_cast<int>(c.verdict));
  }
}

void print_table(const std::vector<MethodRun>& runs, const Reference& ref) {
  std::printf("%-8s %12s %9s %10s %10s %8s %8s %10s %10s %6s\n", "method", "us/config", "speedup",
              "no mesh", "colliding", "missed", "alarms", "err mean", "err max", "viol.");
  std::printf("%-8s %12s %9s %10s %10s %8s %8s %10s %10s %6s\n", "", "", "vs exact", "", "", "", "",
              "(mm)", "(mm)", "");
  const std::size_t n = ref.sampled.size();
  const double em = runs[0].micros;
  for (int k : {0, 1})
    print_row(runs[k], ref, em, error_stats(n, [&](std::size_t) { return 0.0; }));
  print_row(runs[2], ref, em,
            error_stats(n, [&](std::size_t i) { return ref.exact[i] - ref.lower[i]; }));
  print_row(runs[3], ref, em,
            error_stats(n, [&](std::size_t i) { return ref.upper[i] - ref.exact[i]; }));
  for (int k : {4, 5})
    print_row(runs[k], ref, em, error_stats(n, [&](std::size_t i) {
                const double lo = ref.exact[i] - ref.lower[i], hi = ref.upper[i] - ref.exact[i];
                return std::min(lo, hi) < 0.0 ? std::min(lo, hi) : std::max(lo, hi);
              }));
}

void print_setup(const Options& o, const mb::BenchRobot& robot, const mf::RobotBounds& bounds,
                 const mb::BenchScene& scene, std::size_t by_default) {
  std::size_t inner = 0, outer = 0;
  for (const medspheres::Link& l : robot.model.links) {
    inner += l.spheres.inner.size();
    outer += l.spheres.outer.size();
  }
  std::printf("robot %s: %zu links with geometry, %zu inner + %zu outer spheres, %zu triangles\n",
              o.robot.urdf.c_str(), bounds.geometries().size(), inner, outer, robot.triangles);
  std::printf("spheres: %s\n", robot.spheres_from.c_str());
  std::printf(
      "scene (seed %u): %zu boxes, %zu meshes (%zu triangles), octomap of %zu points: "
      "%zu cells of %.3f m\n",
      o.seed, scene.boxes, scene.meshes, scene.mesh_triangles, scene.cloud_points,
      scene.octree_cells, scene.octree_resolution);
  std::printf(
      "pairs: %zu links x %zu scene objects, %zu self pairs%s (adjacent links, "
      "%zu within the margin at the default configuration%s excluded)\n",
      bounds.geometries().size(), scene.objects.size(), bounds.self_pairs().size(),
      o.self ? "" : " (not checked)", by_default, o.srdf.empty() ? "" : ", the SRDF's");
  std::printf("%zu configurations (seed %u), margin %.4g m\n\n", o.configs, o.seed, o.margin);
}

// The methods' ratios, and where the certified bounds (runs[4]) spend their time.
void print_ratios(const std::vector<MethodRun>& runs, const mf::RobotBounds& bounds,
                  std::size_t configs) {
  const MethodRun& b = runs[4];
  const double n = static_cast<double>(configs);
  const double with_mesh = n - static_cast<double>(b.mesh_free + b.undecided);
  std::printf(
      "\nsets alone through FCL (medspheres::fcl::distance): outer %.1fx, inner %.1fx faster "
      "than exact, %.1fx and %.1fx than exact+\n",
      runs[0].micros / runs[2].micros, runs[0].micros / runs[3].micros,
      runs[1].micros / runs[2].micros, runs[1].micros / runs[3].micros);
  std::printf("bounds: %.1fx faster than exact+ (the same pair order and scene skip)\n",
              runs[1].micros / b.micros);
  std::printf("bounds: %zu configurations left undecided (counted as colliding)\n", b.undecided);
  std::printf(
      "bounds: %zu witness sphere pairs (SelfPairOrder) decided %zu configurations "
      "(%.1f%%) with no walk\n",
      bounds.witnesses().size(), b.by_witness, 100.0 * b.by_witness / n);
  std::printf(
      "bounds: the %.0f configurations that queried a mesh took %.1f%% of its time (%.1f us "
      "each), the others %.1f us each\n",
      with_mesh, 100.0 * b.mesh_micros / (b.micros * n),
      with_mesh > 0 ? b.mesh_micros / with_mesh : 0.0,
      (b.micros * n - b.mesh_micros) / std::max(1.0, n - with_mesh));
}

// How many configurations the reference finds within the margin, and where the exact
// methods disagree with it.
void print_reference(const Options& o, const std::vector<MethodRun>& runs, const Reference& ref,
                     double ref_seconds) {
  const std::size_t configs = ref.colliding.size();
  std::size_t truth = 0, disagree = 0, disagree_plus = 0;
  for (std::size_t i = 0; i < configs; ++i) {
    truth += ref.colliding[i];
    disagree += ref.colliding[i] != runs[0].colliding[i];
    disagree_plus += ref.colliding[i] != runs[1].colliding[i];
  }
  std::printf(
      "\nreference: %zu of %zu configurations within %.4g m (%.1f s); exact and exact+ (FCL's "
      "octree) and the reference (the cells as a mesh) disagree on %zu and %zu; distance errors "
      "over %zu configurations (every %zu-th)\n",
      truth, configs, o.margin, ref_seconds, disagree, disagree_plus, ref.sampled.size(),
      o.distance_every);
}

// The robot checker's rows (print_checker_rows) on the same configurations and reference.
void checker_rows(const Options& o, const mb::BenchRobot& robot,
                  const std::vector<const ::fcl::CollisionObjectd*>& objects,
                  const mb::NamePairs& disabled, const std::vector<Eigen::VectorXd>& configs,
                  const Reference& ref, double exact_micros) {
  mb::RobotSource planner_source = o.robot;
  planner_source.spheres_per_link = o.planner_spheres;
  const mb::BenchRobot planner =
      o.planner_spheres == o.robot.spheres_per_link ? robot : mb::load_bench_robot(planner_source);
  mb::CheckerBenchInput in;
  in.planner = &planner;
  in.fine = &robot;
  in.scene = objects;
  in.disabled = disabled;
  in.configs = configs;
  in.reference = ref.colliding;
  in.margin = o.margin;
  in.self = o.self;
  in.exact_micros = exact_micros;
  in.edge_length = o.edge_length;
  in.resolution = o.resolution;
  std::printf("\nplanner sets: %s\n", planner.spheres_from.c_str());
  mb::print_checker_rows(in);
}

// With --explain: every configuration the bounds missed, and every distance outside its
// bounds, pair by pair.
void explain_misses(const Options& o, const mf::RobotBounds& bounds,
                    mb::ExactRobot& exact_reference, const std::vector<Eigen::VectorXd>& configs,
                    const std::vector<const ::fcl::CollisionObjectd*>& objects,
                    const std::vector<MethodRun>& runs, const Reference& ref) {
  for (std::size_t i = 0; i < configs.size() && o.explain; ++i)
    if (ref.colliding[i] && !runs[4].colliding[i]) {
      const mf::RobotCollideResult c =
          mf::robot_collide(bounds, configs[i], objects, o.self, o.margin);
      std::printf("bounds missed configuration %zu: verdict %d, %zu mesh fallbacks\n", i,
                  static_cast<int>(c.verdict), c.mesh_fallbacks);
      explain_near(bounds, exact_reference, configs[i], objects, o.self, o.margin);
    }
  for (std::size_t k = 0; k < ref.sampled.size() && o.explain; ++k)
    if (ref.exact[k] < ref.lower[k] || ref.exact[k] > ref.upper[k]) {
      std::printf("configuration %zu: exact %.9g outside [%.9g, %.9g]\n", ref.sampled[k],
                  ref.exact[k], ref.lower[k], ref.upper[k]);
      explain(bounds, exact_reference, configs[ref.sampled[k]], objects, o.self);
    }
}

int run(const Options& o) {
  const mb::BenchRobot robot = mb::load_bench_robot(o.robot);
  const mb::BenchScene scene = mb::make_scene(o.seed, o.meshes, o.scale);
  const std::vector<const ::fcl::CollisionObjectd*> objects = scene.pointers();
  std::size_t by_default = 0;
  const mb::NamePairs disabled = mb::disabled_pairs(o.srdf, o.margin, robot, by_default);
  const mf::RobotBounds plain(robot.model, robot.meshes, disabled);
  const auto t_order = Clock::now();
  const mf::RobotBounds bounds(robot.model, robot.meshes, disabled, {},
                               {o.order_samples, o.margin, o.seed + 1});
  const double order_seconds = mb::seconds_since(t_order);
  mb::ExactRobot exact(plain, robot.exact, objects);
  // exact+ walks the pairs in every configuration: its order is the greedy one over all
  // the samples (no witnesses, which robot_collide's order defers to).
  const mf::RobotBounds pair_order(robot.model, robot.meshes, disabled, {},
                                   {o.order_samples, o.margin, o.seed + 1, 0});
  mb::ExactRobot exact_tricks(pair_order, robot.exact, objects, {}, true);
  mb::Solids solids = robot.solids;
  solids.insert(scene.solids.begin(), scene.solids.end());
  mb::ExactRobot exact_reference(bounds, robot.exact, scene.pointers(true), solids);
  print_setup(o, robot, bounds, scene, by_default);
  std::printf("self pairs ordered by %zu seeded configurations (seed %u): %.2f s\n\n",
              o.order_samples, o.seed + 1, order_seconds);
  if (exact.missing_links() > 0)
    std::printf("note: %zu links have no exact geometry: the exact side skips them\n",
                exact.missing_links());
  const auto configs =
      mf::sample_configurations(robot.model, bounds.kinematics(), o.configs, o.seed);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const mb::SphereRobot outer(bounds, robot.model, false), inner(bounds, robot.model, true);
  std::vector<std::pair<std::string, Method>> methods;
  methods.emplace_back(std::string("exact"), [&](std::size_t i, MethodRun& r) {
    r.uses_mesh = true;
    return exact.collide(bounds.poses(configs[i], I), o.self, o.margin);
  });
  methods.emplace_back(std::string("exact+"), [&](std::size_t i, MethodRun& r) {
    r.uses_mesh = true;
    return exact_tricks.collide(bounds.poses(configs[i], I), o.self, o.margin);
  });
  methods.emplace_back(std::string("outer"), [&](std::size_t i, MethodRun&) {
    return outer.collide(bounds.poses(configs[i], I), objects, o.self, o.margin);
  });
  methods.emplace_back(std::string("inner"), [&](std::size_t i, MethodRun&) {
    return inner.collide(bounds.poses(configs[i], I), objects, o.self, o.margin);
  });
  // Undecided (a pair the spheres cannot decide and no mesh pair can settle, e.g. a link of
  // sphere primitives only against a meshed link) counts as colliding, as a planner must
  // take it.
  auto certified = [&](const mf::RobotBounds& checker) {
    return [&](std::size_t i, MethodRun& r) {
      r.uses_mesh = true;
      const mf::RobotCollideResult c =
          mf::robot_collide(checker, configs[i], objects, o.self, o.margin);
      r.queried_mesh = c.mesh_fallbacks > 0;
      if (c.mesh_fallbacks == 0 && c.verdict != medspheres::BoundsVerdict::undecided) ++r.mesh_free;
      if (c.verdict == medspheres::BoundsVerdict::undecided) ++r.undecided;
      if (c.by_witness) ++r.by_witness;
      return c.verdict != medspheres::BoundsVerdict::free;
    };
  };
  methods.emplace_back("bounds", certified(bounds));
  methods.emplace_back("bounds/g", certified(plain));
  const std::vector<MethodRun> runs = run_methods(methods, configs.size());
  const auto t0 = Clock::now();
  const Reference ref = reference(bounds, exact_reference, configs, objects, o.self, o.margin,
                                  std::max<std::size_t>(o.distance_every, 1));
  const double ref_seconds = mb::seconds_since(t0);
  print_table(runs, ref);
  std::printf(
      "\nforward kinematics (RobotBounds::poses, in every method's time): %.2f us per "
      "configuration\n",
      kinematics_micros(bounds, configs));
  print_ratios(runs, bounds, configs.size());
  print_reference(o, runs, ref, ref_seconds);
  if (o.breakdown > 0) {
    std::vector<Poses> poses;
    for (std::size_t i = 0; i < std::min(o.breakdown, configs.size()); ++i)
      poses.push_back(bounds.poses(configs[i], I));
    mb::print_breakdown(poses, scene, bounds.geometries().size(), bounds.self_pairs().size(), exact,
                        outer, inner, o.self, o.margin);
  }
  if (o.checker) checker_rows(o, robot, objects, disabled, configs, ref, runs[0].micros);
  explain_misses(o, bounds, exact_reference, configs, objects, runs, ref);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  mb::restart_with_passive_openmp(argv);
  Options o = parse(argc, argv);
  return mb::run_robot_bench("bench_robot", o.generated, o.robot.cache_dir, o.robot.urdf,
                             [&o] { return run(o); });
}
