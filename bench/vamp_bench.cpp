// VAMP's collision checker beside medspheres' RobotChecker on VAMP's own Panda, in one run:
// the same configurations, scenes and edges, on one thread. VAMP's kernel is code generated
// for its 59 hand-placed spheres (KavrakiLab/vamp, src/impl/vamp/robots/panda.hh); the
// checker runs once on the same 59 spheres (an engine against an engine: their verdicts must
// agree, which the table counts) and once on the covering sets that `medspheres robot` baked
// from the same URDF. With --mbm, MotionBenchMaker's problems (mbm_problems.h) are planned by
// VAMP's RRTConnect, once with VAMP's kernel and once per sphere set with the checker in its
// place (CheckedPanda: VAMP's planner asks the checker), a checker per problem made by
// with_scene().
//
// Built only when MEDSPHERES_VAMP_DIR, MEDSPHERES_PDQSORT_DIR and MEDSPHERES_NIGH_DIR name
// checkouts of VAMP, pdqsort and nigh (bench/CMakeLists.txt); CI has none of them.
// docs/checker.md ("Beside VAMP, on VAMP's Panda") has the commands and the figures.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <vamp/collision/factory.hh>
#include <vamp/planning/rrtc.hh>
#include <vamp/planning/validate.hh>
#include <vamp/random/halton.hh>
#include <vamp/robots/panda.hh>

#include "bench_args.h"
#include "bench_percentile.h"
#include "bench_timing.h"
#include "mbm_problems.h"
#include "medspheres/check/robot_checker.h"
#include "medspheres/formats/srdf_disabled_collisions.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/robot_bake/evaluate_set_robot.h"
#include "medspheres/robot_file.h"

namespace {

using namespace medspheres;
namespace mb = medspheres::bench;
using Panda = vamp::robots::Panda;
constexpr std::size_t kRake = vamp::FloatVectorWidth;
using VampScene = vamp::collision::Environment<vamp::FloatVector<kRake>>;
constexpr std::size_t kDof = Panda::dimension;

struct Options {
  std::string robot_file, vamp_spheres, srdf;
  std::size_t configs = 100000, edges = 2000;
  unsigned seed = 1;
  double edge_length = 1.0;
  int repeats = 3;
  std::string mbm;  // MotionBenchMaker's problems folder
  std::size_t mbm_problems = 100;
  std::size_t max_cells = check::CheckerOptions{}.max_cells;
};

using mb::Primitive;
using mb::PrimitiveScene;

Primitive sphere(double x, double y, double z, double r) {
  Primitive p;
  p.pose.translation() = Eigen::Vector3d(x, y, z);
  p.radius = r;
  return p;
}

Primitive box(const Eigen::Vector3d& centre, double yaw, const Eigen::Vector3d& half) {
  Primitive p;
  p.kind = Primitive::Kind::box;
  p.pose.translate(centre).rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  p.half = half;
  return p;
}

// VAMP's sphere cage (scripts/cpp/rrtc_example.cc): 14 balls of radius 0.2 about the base.
PrimitiveScene cage() {
  PrimitiveScene s{"cage", {}};
  const double c[14][3] = {{0.55, 0, 0.25},     {0.35, 0.35, 0.25},   {0, 0.55, 0.25},
                           {-0.55, 0, 0.25},    {-0.35, -0.35, 0.25}, {0, -0.55, 0.25},
                           {0.35, -0.35, 0.25}, {0.35, 0.35, 0.8},    {0, 0.55, 0.8},
                           {-0.35, 0.35, 0.8},  {-0.55, 0, 0.8},      {-0.35, -0.35, 0.8},
                           {0, -0.55, 0.8},     {0.35, -0.35, 0.8}};
  for (const auto& p : c) s.items.push_back(sphere(p[0], p[1], p[2], 0.2));
  return s;
}

// A table under the arm (its top 5 cm below the base, which VAMP's spheres reach 3 cm
// below) and \p n seeded boxes turned about z in a ring 0.35 to 0.8 m from the base.
PrimitiveScene boxes(unsigned seed, int n) {
  PrimitiveScene s{"boxes", {box({0.5, 0.0, -0.07}, 0.0, {0.6, 0.8, 0.02})}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * u(rng), d = 0.35 + 0.45 * u(rng), z = 0.1 + 0.9 * u(rng);
    const double yaw = M_PI * u(rng);
    const Eigen::Vector3d half(0.03 + 0.07 * u(rng), 0.03 + 0.07 * u(rng), 0.03 + 0.07 * u(rng));
    s.items.push_back(box({d * std::cos(a), d * std::sin(a), z}, yaw, half));
  }
  return s;
}

// VAMP's environment of the same primitives: a box from its centre, axes and half extents
// (not from Euler angles), a capsule from its segment's ends.
VampScene vamp_scene(const PrimitiveScene& s) {
  namespace f = vamp::collision::factory;
  vamp::collision::Environment<float> e;
  for (const Primitive& p : s.items) {
    const Eigen::Vector3f c = p.pose.translation().cast<float>();
    const Eigen::Matrix3f R = p.pose.linear().cast<float>();
    if (p.kind == Primitive::Kind::sphere) {
      e.spheres.push_back(f::sphere::flat(c.x(), c.y(), c.z(), float(p.radius)));
    } else if (p.kind == Primitive::Kind::box) {
      const Eigen::Vector3f h = p.half.cast<float>();
      e.cuboids.emplace_back(c.x(), c.y(), c.z(), R(0, 0), R(1, 0), R(2, 0), R(0, 1), R(1, 1),
                             R(2, 1), R(0, 2), R(1, 2), R(2, 2), h.x(), h.y(), h.z());
    } else {
      const Eigen::Vector3f a = c - 0.5f * float(p.length) * R.col(2),
                            b = c + 0.5f * float(p.length) * R.col(2);
      e.capsules.push_back(
          f::capsule::endpoints::flat(a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), float(p.radius)));
    }
  }
  e.sort();
  return VampScene(e);
}

check::Scene our_scene(const PrimitiveScene& s) {
  check::Scene scene;
  for (const Primitive& p : s.items) {
    if (p.kind == Primitive::Kind::sphere)
      scene.add_sphere(p.pose.translation(), p.radius);
    else if (p.kind == Primitive::Kind::box)
      scene.add_box(2 * p.half, p.pose);
    else
      scene.add_capsule(p.radius, p.length, p.pose);
  }
  return scene;
}

// The robot file's model with each link's covering set replaced by VAMP's spheres (links
// VAMP gives none have none).
RobotModel with_vamp_spheres(RobotModel model, const std::string& path) {
  const auto spheres = read_robot_spheres(path);
  for (Link& l : model.links) {
    const auto it = spheres.find(l.name);
    l.spheres = LinkSpheres{};
    if (it != spheres.end()) l.spheres.outer = it->second;
  }
  return model;
}

struct Row {
  std::string scene, spheres, engine;
  double ns_each = 0, ns_free = 0, ns_block = 0, us_edge = 0;
  std::size_t colliding = 0, blocks_colliding = 0, edges_colliding = 0;
  std::string disagree = "-";  // configurations whose verdict differs from VAMP's
  bool has_block = false;
};

// The least CPU nanoseconds per item of \p n over \p repeats runs of \p run.
template <class F>
double best_ns(int repeats, std::size_t n, F&& run) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = mb::thread_cpu_micros();
    run();
    best = std::min(best, (mb::thread_cpu_micros() - t0) * 1e3 /
                              static_cast<double>(std::max<std::size_t>(n, 1)));
  }
  return best;
}

using Block = Panda::ConfigurationBlock<kRake>;
using Blocks = std::vector<Block>;  // C++17's allocator honours the blocks' alignment

// Configurations \p rows of \p q (n x kDof) as VAMP's blocks: each row's eight copies (its
// validate() of one configuration) when \p copies, else eight rows a block.
Blocks blocks_of(const std::vector<double>& q, const std::vector<std::size_t>& rows, bool copies) {
  Blocks out;
  const std::size_t step = copies ? 1 : kRake;
  for (std::size_t first = 0; first + step <= rows.size(); first += step) {
    Block block;
    for (std::size_t j = 0; j < kDof; ++j) {
      std::array<float, kRake> lane{};
      for (std::size_t k = 0; k < kRake; ++k)
        lane[k] = static_cast<float>(q[rows[first + (copies ? 0 : k)] * kDof + j]);
      block[j] = vamp::FloatVector<kRake>(lane);
    }
    out.push_back(block);
  }
  return out;
}

Panda::Configuration config_of(const std::vector<double>& q, std::size_t i) {
  std::array<float, kDof> a{};
  for (std::size_t j = 0; j < kDof; ++j) a[j] = static_cast<float>(q[i * kDof + j]);
  return Panda::Configuration(a);
}

std::vector<std::size_t> all_rows(std::size_t n) {
  std::vector<std::size_t> rows(n);
  for (std::size_t i = 0; i < n; ++i) rows[i] = i;
  return rows;
}

// The rows of \p q as one matrix (n x kDof).
std::vector<double> pick(const std::vector<double>& q, const std::vector<std::size_t>& rows) {
  std::vector<double> out;
  for (std::size_t i : rows)
    out.insert(out.end(), q.begin() + i * kDof, q.begin() + (i + 1) * kDof);
  return out;
}

// How many of \p blocks fkcc finds colliding (in any lane); into \p hit per block when given.
std::size_t vamp_check(const VampScene& scene, const Blocks& blocks, std::vector<char>* hit) {
  std::size_t colliding = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const bool h = !Panda::fkcc<kRake>(scene, blocks[b]);
    colliding += h;
    if (hit) (*hit)[b] = h;
  }
  return colliding;
}

// VAMP: one verdict per configuration (a block of eight copies, as its validate() runs one),
// the same on the free ones alone, eight distinct configurations a block (its planners' use:
// one verdict for the eight), and validate_motion on each edge. \p verdicts: per
// configuration; \p free_rows: those it finds free.
Row run_vamp(const Options& o, const PrimitiveScene& s, const std::vector<double>& q,
             const std::vector<double>& e0, const std::vector<double>& e1,
             std::vector<char>& verdicts, std::vector<std::size_t>& free_rows) {
  const VampScene scene = vamp_scene(s);
  const std::size_t n = q.size() / kDof, m = e0.size() / kDof;
  Row row{s.name, "VAMP's 59", "VAMP"};
  row.has_block = true;
  const Blocks each = blocks_of(q, all_rows(n), true), eight = blocks_of(q, all_rows(n), false);
  verdicts.assign(n, 0);
  row.ns_each = best_ns(o.repeats, n, [&] { row.colliding = vamp_check(scene, each, &verdicts); });
  free_rows.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (!verdicts[i]) free_rows.push_back(i);
  const Blocks free_each = blocks_of(q, free_rows, true);
  volatile std::size_t sink = 0;  // keeps the pure kernel's calls from being dropped
  row.ns_free = best_ns(o.repeats, free_rows.size(),
                        [&] { sink = sink + vamp_check(scene, free_each, nullptr); });
  row.ns_block = best_ns(o.repeats, eight.size() * kRake,
                         [&] { row.blocks_colliding = vamp_check(scene, eight, nullptr); });
  row.us_edge = 1e-3 * best_ns(o.repeats, m, [&] {
                  row.edges_colliding = 0;
                  for (std::size_t i = 0; i < m; ++i)
                    row.edges_colliding +=
                        !vamp::planning::validate_motion<Panda, kRake, Panda::resolution>(
                            config_of(e0, i), config_of(e1, i), scene);
                });
  return row;
}

// The checker on \p model's covering sets, spheres mode, margin 0, one thread: every
// configuration, the free ones of VAMP's (\p free_rows) alone, and the edges; verdicts that
// differ from \p reference (when given) are counted.
Row run_ours(const Options& o, const PrimitiveScene& s, const RobotModel& model,
             const std::vector<std::pair<std::string, std::string>>& disabled,
             const std::string& spheres, const std::vector<double>& q,
             const std::vector<std::size_t>& free_rows, const std::vector<double>& e0,
             const std::vector<double>& e1, const std::vector<char>* reference) {
  check::CheckerOptions options;
  options.disabled = disabled;
  options.order_seed = o.seed + 7919;
  options.max_cells = o.max_cells;
  const check::RobotChecker checker(model, our_scene(s), options);
  const std::size_t n = q.size() / kDof, m = e0.size() / kDof;
  const std::vector<double> q_free = pick(q, free_rows);
  std::vector<check::Verdict> out(n), free_out(free_rows.size()), edge_out(m);
  Row row{s.name, spheres, "medspheres"};
  row.ns_each = best_ns(o.repeats, n,
                        [&] { checker.check(q.data(), n, check::Mode::spheres, out.data(), 1); });
  row.ns_free = best_ns(o.repeats, free_rows.size(), [&] {
    checker.check(q_free.data(), free_rows.size(), check::Mode::spheres, free_out.data(), 1);
  });
  std::size_t disagree = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool hit = out[i] == check::Verdict::colliding;
    row.colliding += hit;
    if (reference && hit != ((*reference)[i] != 0)) ++disagree;
  }
  if (reference) row.disagree = std::to_string(disagree);
  row.us_edge = 1e-3 * best_ns(o.repeats, m, [&] {
                  checker.check_edges(e0.data(), e1.data(), m, 1.0 / Panda::resolution,
                                      check::Mode::spheres, edge_out.data(), 1);
                });
  row.edges_colliding = static_cast<std::size_t>(
      std::count(edge_out.begin(), edge_out.end(), check::Verdict::colliding));
  return row;
}

// VAMP's Panda whose collision check is a RobotChecker's: VAMP's planners call fkcc on
// blocks of eight configurations (eight samples of a motion, or one configuration eight
// times), and this one asks the checker whether any of them collides.
struct CheckedPanda : Panda {
  static inline const check::RobotChecker* checker = nullptr;

  template <std::size_t rake>
  static bool fkcc(const vamp::collision::Environment<vamp::FloatVector<rake>>&,
                   const ConfigurationBlock<rake>& x) noexcept {
    std::array<double, rake * kDof> q;
    for (std::size_t j = 0; j < kDof; ++j) {
      const auto lane = x[j].to_array();
      for (std::size_t k = 0; k < rake; ++k) q[k * kDof + j] = lane[k];
    }
    return !checker->any_colliding(q.data(), rake);
  }
  template <std::size_t rake>
  static bool fkcc_attach(const vamp::collision::Environment<vamp::FloatVector<rake>>& e,
                          const ConfigurationBlock<rake>& x) noexcept {
    return fkcc<rake>(e, x);
  }
};

struct PlanRow {
  std::size_t problems = 0, valid = 0, solved = 0;
  std::vector<double> plan_us, build_ms;  // per solved problem; per checker built
};

// VAMP's RRTConnect (its default settings, its Halton sampler reset per problem, as its
// evaluate_mbm.py runs it) on problem \p p with Robot's collision check, CPU time, when the
// start and the goal are free.
template <class Robot>
void plan(const VampScene& env, const mb::MbmProblem& p, PlanRow& row) {
  ++row.problems;
  for (const std::vector<double>* q : {&p.start, &p.goal})
    if (!Robot::template fkcc<kRake>(env, blocks_of(*q, {0}, true)[0])) return;
  ++row.valid;
  auto rng = std::make_shared<vamp::rng::Halton<Robot>>();
  const double t0 = mb::thread_cpu_micros();
  const auto result = vamp::planning::RRTC<Robot, kRake, Robot::resolution>::solve(
      config_of(p.start, 0), config_of(p.goal, 0), env, vamp::planning::RRTCSettings{}, rng);
  const double us = mb::thread_cpu_micros() - t0;
  if (result.path.empty()) return;
  ++row.solved;
  row.plan_us.push_back(us);
}

// The median of \p v (bench_percentile.h), 0 for none.
double median(const std::vector<double>& v) {
  return v.empty() ? 0.0 : mb::percentile(v, 0.5);
}

// Every problem planned by VAMP with its own kernel, then with a checker of each model for
// the problem's scene (with_scene of one built once, its time apart).
void plan_problems(const std::vector<mb::MbmProblem>& problems,
                   const std::vector<std::pair<std::string, const RobotModel*>>& models,
                   const std::vector<std::vector<std::pair<std::string, std::string>>>& disabled,
                   const Options& o) {
  std::map<std::string, std::vector<PlanRow>> sets;
  std::vector<check::RobotChecker> base;
  for (std::size_t m = 0; m < models.size(); ++m) {
    check::CheckerOptions options;
    options.disabled = disabled[m];
    options.order_seed = o.seed + 7919;
    options.max_cells = o.max_cells;
    base.emplace_back(*models[m].second, check::Scene(), options);
  }
  for (const mb::MbmProblem& p : problems) {
    std::vector<PlanRow>& rows = sets[p.set];
    rows.resize(1 + models.size());
    const VampScene env = vamp_scene(p.scene);
    plan<Panda>(env, p, rows[0]);
    for (std::size_t m = 0; m < models.size(); ++m) {
      const check::Scene scene = our_scene(p.scene);
      const double t0 = mb::thread_cpu_micros();
      const check::RobotChecker checker = base[m].with_scene(scene);
      rows[1 + m].build_ms.push_back(1e-3 * (mb::thread_cpu_micros() - t0));
      CheckedPanda::checker = &checker;
      plan<CheckedPanda>(env, p, rows[1 + m]);
    }
  }
  std::printf(
      "\n| problem set | checker | valid / problems | solved | plan us, median | plan us, "
      "mean | checker built in ms, median |\n|---|---|---|---|---|---|---|\n");
  for (const auto& [set, rows] : sets)
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const PlanRow& row = rows[r];
      double mean = 0;
      for (double us : row.plan_us) mean += us / double(row.plan_us.size());
      const std::string name =
          r == 0 ? "VAMP's own (VAMP's 59)" : "medspheres, " + models[r - 1].first;
      const std::string build = r == 0 ? "-" : std::to_string(median(row.build_ms)).substr(0, 6);
      std::printf("| %s | %s | %zu / %zu | %zu | %.1f | %.1f | %s |\n", set.c_str(), name.c_str(),
                  row.valid, row.problems, row.solved, median(row.plan_us), mean, build.c_str());
    }
}

// Configurations uniform within VAMP's joint limits, and edges of o.edge_length from such
// configurations, clamped into the limits.
void draw(const Options& o, std::vector<double>& q, std::vector<double>& e0,
          std::vector<double>& e1) {
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  auto sample = [&](std::vector<double>& v) {
    for (std::size_t j = 0; j < kDof; ++j) v.push_back(Panda::s_a[j] + Panda::s_m[j] * u(rng));
  };
  for (std::size_t i = 0; i < o.configs; ++i) sample(q);
  for (std::size_t i = 0; i < o.edges; ++i) {
    sample(e0);
    std::array<double, kDof> d{};
    double norm = 0;
    for (double& x : d) {
      x = g(rng);
      norm += x * x;
    }
    for (std::size_t j = 0; j < kDof; ++j) {
      const double lo = Panda::s_a[j], hi = lo + Panda::s_m[j];
      const double x = e0[i * kDof + j] + o.edge_length * d[j] / std::sqrt(norm);
      e1.push_back(std::clamp(x, lo, hi));
    }
  }
}

void print(const std::vector<Row>& rows) {
  std::printf(
      "| scene | spheres | checker | ns/config, one verdict each | colliding | "
      "disagree with VAMP | ns/config, VAMP's free ones | ns/config, 8 a verdict | "
      "blocks colliding | us/edge | edges colliding |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    char block[64] = "-", blocks[32] = "-";
    if (r.has_block) {
      std::snprintf(block, sizeof block, "%.1f", r.ns_block);
      std::snprintf(blocks, sizeof blocks, "%zu", r.blocks_colliding);
    }
    std::printf("| %s | %s | %s | %.1f | %zu | %s | %.1f | %s | %s | %.2f | %zu |\n",
                r.scene.c_str(), r.spheres.c_str(), r.engine.c_str(), r.ns_each, r.colliding,
                r.disagree.c_str(), r.ns_free, block, blocks, r.us_edge, r.edges_colliding);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  mb::Args args("bench_vamp", "VAMP's checker beside medspheres' on VAMP's Panda");
  args.add("--robot-file", o.robot_file,
           "medspheres robot of VAMP's resources/panda/panda.urdf: NAME.robot.json")
      ->required();
  args.add("--vamp-spheres", o.vamp_spheres, "VAMP's resources/panda/panda_spherized.urdf")
      ->required();
  args.add("--srdf", o.srdf, "VAMP's resources/panda/panda.srdf (its pairs left out)")->required();
  args.add("--configs", o.configs, "Seeded configurations");
  args.add("--edges", o.edges, "Seeded edges");
  args.add("--edge-length", o.edge_length, "Edges: joint-space length");
  args.add("--seed", o.seed, "Seed of the configurations, edges and boxes");
  args.add("--repeats", o.repeats, "Each time the best of this many runs");
  args.add("--mbm", o.mbm,
           "MotionBenchMaker's problems (VAMP's resources/panda/problems.tar.bz2, extracted: "
           "the folder of the sets): plan each with VAMP's RRTConnect");
  args.add("--mbm-problems", o.mbm_problems, "With --mbm: the first N problems of each set");
  args.add("--max-cells", o.max_cells, "The checkers' scene grid: cells at most");
  args.parse(argc, argv);
  try {
    const RobotModel ours = load_robot(o.robot_file);
    const RobotModel vamp = with_vamp_spheres(ours, o.vamp_spheres);
    const std::vector<std::string> joints(Panda::joint_names.begin(), Panda::joint_names.end());
    if (KinematicTree(ours).joint_names() != joints)
      throw std::runtime_error(o.robot_file +
                               ": its joints are not VAMP's Panda's panda_joint1 to 7");
    std::vector<std::pair<std::string, std::string>> srdf, matrix;
    for (const auto& d : formats::load_srdf_disabled_collisions(o.srdf))
      srdf.emplace_back(d.link1, d.link2);
    if (ours.planner && ours.planner->self_collision)
      matrix = ignored_pairs(*ours.planner->self_collision);
    std::vector<double> q, e0, e1;
    draw(o, q, e0, e1);
    std::printf(
        "VAMP's Panda, %zu configurations, %zu edges of length %.2f at resolution 1/%zu, "
        "seed %u, one thread, CPU time, best of %d; AVX2 width %zu\n\n",
        o.configs, o.edges, o.edge_length, Panda::resolution, o.seed, o.repeats, kRake);
    std::vector<Row> rows;
    for (const PrimitiveScene& s : {cage(), boxes(o.seed, 12)}) {
      std::vector<char> reference;
      std::vector<std::size_t> free_rows;
      rows.push_back(run_vamp(o, s, q, e0, e1, reference, free_rows));
      rows.push_back(run_ours(o, s, vamp, srdf, "VAMP's 59", q, free_rows, e0, e1, &reference));
      rows.push_back(
          run_ours(o, s, ours, matrix, "covers (robot file)", q, free_rows, e0, e1, nullptr));
    }
    print(rows);
    if (!o.mbm.empty())
      plan_problems(mb::load_mbm_problems(o.mbm, o.mbm_problems, joints),
                    {{"VAMP's 59", &vamp}, {"covers (robot file)", &ours}}, {srdf, matrix}, o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_vamp: %s\n", e.what());
    return 2;
  }
  return 0;
}
