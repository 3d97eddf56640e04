// bench_robot's checker rows (robot_bench_check.h).

#include "robot_bench_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <stdexcept>

#include <fcl/fcl.h>
#include <omp.h>

#include "bench_timing.h"
#include "medspheres/fcl/certified_checker.h"
#include "medspheres/fcl/scene_from_fcl.h"
#include "medspheres/forward_kinematics.h"

namespace medspheres::bench {
namespace {

using check::Verdict;

// The best of `repeats` runs of f: CPU time of the thread (one thread) or wall time.
double best_micros(int repeats, bool wall, const std::function<void()>& f) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeats; ++r) {
    const double t0 = thread_cpu_micros();
    const auto w0 = Clock::now();
    f();
    best = std::min(best, wall ? micros_since(w0) : thread_cpu_micros() - t0);
  }
  return best;
}

struct Row {
  Row(std::string n, int t) : name(std::move(n)), threads(t) {}
  std::string name;
  int threads = 1;
  double micros = 0.0;  // per configuration
  std::vector<char> colliding;
  std::string note;
  std::vector<std::size_t> subset;  // the configurations of colliding; empty: all, in order
};

void print_row(const Row& r, const CheckerBenchInput& in) {
  std::size_t colliding = 0, missed = 0, alarms = 0;
  for (std::size_t i = 0; i < r.colliding.size(); ++i) {
    const bool truth = in.reference[r.subset.empty() ? i : r.subset[i]];
    colliding += r.colliding[i];
    missed += truth && !r.colliding[i];
    alarms += !truth && r.colliding[i];
  }
  std::printf("%-10s %7s %10.3f %10.0f %9.0fx %10zu %7zu %7zu  %s\n", r.name.c_str(),
              r.threads == 1 ? "1" : "all", r.micros, 1e3 * r.micros, in.exact_micros / r.micros,
              colliding, missed, alarms, r.note.c_str());
}

std::vector<double> rows_of(const std::vector<Eigen::VectorXd>& configs) {
  std::vector<double> q;
  for (const Eigen::VectorXd& c : configs) q.insert(q.end(), c.data(), c.data() + c.size());
  return q;
}

// The same checks as the spheres mode, written as a user without the checker would: every
// covering sphere an fcl::Sphere grown by the margin (half of it for a self pair, so that
// two touch exactly when within the margin), posed by forward kinematics, fcl::collide
// against every scene object, then every sphere pair of every self pair; the first
// collision ends the configuration.
class FclSphereLoop {
 public:
  FclSphereLoop(const RobotModel& model, const check::RobotChecker& checker,
                const std::vector<const ::fcl::CollisionObjectd*>& scene, double margin, bool self)
      : tree_(model), scene_(scene), self_(self), pairs_(checker.self_pairs()) {
    for (const std::string& name : checker.links()) {
      link_.push_back(tree_.link_index(name));
      std::vector<Part> parts;
      for (const Sphere& s : model.find_link(name)->spheres.outer.spheres)
        parts.push_back({s.center,
                         std::make_unique<::fcl::CollisionObjectd>(
                             std::make_shared<::fcl::Sphered>(s.radius + margin)),
                         std::make_unique<::fcl::CollisionObjectd>(
                             std::make_shared<::fcl::Sphered>(s.radius + margin / 2))});
      parts_.push_back(std::move(parts));
    }
  }

  bool collide(const Eigen::VectorXd& q) {
    const std::vector<Eigen::Isometry3d> X = tree_.link_poses(q);
    ::fcl::CollisionRequestd request;
    ::fcl::CollisionResultd result;
    for (std::size_t l = 0; l < parts_.size(); ++l)
      for (Part& p : parts_[l]) {
        const Eigen::Vector3d c = X[link_[l]] * p.center;
        p.scene->setTranslation(c);
        p.self->setTranslation(c);
        p.scene->computeAABB();
        p.self->computeAABB();
        for (const ::fcl::CollisionObjectd* o : scene_) {
          result.clear();
          if (::fcl::collide(p.scene.get(), o, request, result) > 0) return true;
        }
      }
    if (!self_) return false;
    for (const auto& [a, b] : pairs_)
      for (const Part& p : parts_[a])
        for (const Part& r : parts_[b]) {
          result.clear();
          if (::fcl::collide(p.self.get(), r.self.get(), request, result) > 0) return true;
        }
    return false;
  }

 private:
  struct Part {
    Eigen::Vector3d center;
    std::unique_ptr<::fcl::CollisionObjectd> scene, self;
  };
  KinematicTree tree_;
  std::vector<const ::fcl::CollisionObjectd*> scene_;
  bool self_;
  std::vector<std::pair<std::size_t, std::size_t>> pairs_;
  std::vector<std::size_t> link_;
  std::vector<std::vector<Part>> parts_;
};

// The fallback's joint-space tables: how many, their cells, the share decided.
void print_tables(const fcl::CertifiedChecker& c, double seconds) {
  std::size_t tables = 0, cells = 0, free = 0, colliding = 0, stored = 0;
  for (const auto& [a, b] : c.fallback().self_pairs())
    if (const fcl::PairJointTable* t = c.table(a, b)) {
      ++tables;
      cells += t->cells();
      free += t->free_cells();
      colliding += t->colliding_cells();
      stored += t->stored();
    }
  if (tables > 0)
    std::printf(
        "joint-space tables: %zu self pairs, %zu cells (%zu free, %zu colliding), %zu read from "
        "the store; the certified checker built in %.1f s\n",
        tables, cells, free, colliding, stored, seconds);
}

// Edges: from each configuration towards the next, cut to edge_length.
void make_edges(const CheckerBenchInput& in, std::vector<double>& q0, std::vector<double>& q1) {
  for (std::size_t i = 0; i + 1 < in.configs.size(); ++i) {
    const Eigen::VectorXd d = in.configs[i + 1] - in.configs[i];
    const Eigen::VectorXd end = in.configs[i] + std::min(1.0, in.edge_length / d.norm()) * d;
    q0.insert(q0.end(), in.configs[i].data(), in.configs[i].data() + d.size());
    q1.insert(q1.end(), end.data(), end.data() + d.size());
  }
}

std::vector<char> colliding_of(const std::vector<Verdict>& v) {
  std::vector<char> out;
  for (Verdict x : v) out.push_back(x != Verdict::free);  // undecided as colliding
  return out;
}

std::size_t spheres_of(const RobotModel& m, bool outer) {
  std::size_t n = 0;
  for (const Link& l : m.links) n += outer ? l.spheres.outer.size() : l.spheres.inner.size();
  return n;
}

// Per edge: spheres only and certified, one thread and every core, and spheres only with
// the tests in their default order (`unordered`), one thread; and the edges' verdicts
// against every sample checked as a configuration (spheres only).
void print_edges(const CheckerBenchInput& in, const fcl::CertifiedChecker& certified,
                 const check::RobotChecker& unordered) {
  const check::RobotChecker& spheres = certified.spheres();
  std::vector<double> q0, q1;
  make_edges(in, q0, q1);
  const std::size_t edges = q0.size() / spheres.num_positions();
  std::vector<Verdict> v(edges);
  std::printf("\n%-10s %7s %12s %14s %16s %10s  %s\n", "edges", "threads", "us/edge",
              "configs/edge", "configs/s/core", "colliding", "note");
  for (int certified_mode : {0, 1, 2})  // 2: spheres only, the default order
    for (int threads : {1, 0}) {
      if (threads != 1 && (!in.all_cores || certified_mode == 2)) continue;
      std::size_t checked = 0;
      fcl::FallbackStats stats;
      const check::RobotChecker& plain = certified_mode == 2 ? unordered : spheres;
      const double micros = best_micros(in.repeats, threads != 1, [&] {
        stats = {};
        checked = certified_mode == 1
                      ? certified.check_edges(q0.data(), q1.data(), edges, in.resolution, v.data(),
                                              threads, &stats)
                      : plain.check_edges(q0.data(), q1.data(), edges, in.resolution,
                                          check::Mode::spheres, v.data(), threads);
      });
      const int cores = threads == 1 ? 1 : omp_get_max_threads();
      std::size_t colliding = 0;
      for (Verdict x : v) colliding += x != Verdict::free;
      char note[96] = "";
      if (certified_mode == 1)
        std::snprintf(note, sizeof note, "fallback in %zu samples, %zu pairs to the meshes",
                      stats.configurations, stats.meshes);
      if (certified_mode == 2) std::snprintf(note, sizeof note, "the tests' default order");
      std::printf("%-10s %7s %12.3f %14.1f %16.3g %10zu  %s\n",
                  certified_mode == 1   ? "check/c"
                  : certified_mode == 2 ? "check/s0"
                                        : "check/s",
                  threads == 1 ? "1" : "all", micros / double(edges),
                  double(checked) / double(edges), double(checked) / (micros * 1e-6) / cores,
                  colliding, note);
    }
  // Every sample of every edge as a configuration.
  std::vector<double> samples;
  std::vector<std::size_t> first{0};
  const std::size_t dof = spheres.num_positions();
  for (std::size_t e = 0; e < edges; ++e) {
    const std::size_t n = spheres.edge_steps(&q0[e * dof], &q1[e * dof], in.resolution);
    for (std::size_t k = 0; k <= n; ++k)
      for (std::size_t j = 0; j < dof; ++j)
        samples.push_back(q0[e * dof + j] +
                          double(k) / double(n) * (q1[e * dof + j] - q0[e * dof + j]));
    first.push_back(first.back() + n + 1);
  }
  std::vector<Verdict> each(first.back());
  spheres.check(samples.data(), each.size(), check::Mode::spheres, each.data(), 0);
  spheres.check_edges(q0.data(), q1.data(), edges, in.resolution, check::Mode::spheres, v.data(),
                      0);
  std::size_t agree = 0;
  for (std::size_t e = 0; e < edges; ++e) {
    bool any = false;
    for (std::size_t k = first[e]; k < first[e + 1]; ++k)
      any = any || each[k] == Verdict::colliding;
    agree += any == (v[e] == Verdict::colliding);
  }
  std::printf(
      "edges: %zu of length <= %.3g at resolution %.3g (%zu samples in all); spheres only: %zu of "
      "%zu verdicts as every sample checked alone\n",
      edges, in.edge_length, in.resolution, each.size(), agree, edges);
}

// The learnt orders' first tests (check/s; check/s0 runs them in the default order), and
// the bounds mode's probe.
void print_test_order(const check::RobotChecker& spheres) {
  const check::TestOrder order = spheres.test_order();
  const std::size_t links = spheres.links().size();
  const auto pairs = spheres.self_pairs();
  const auto first = [&](const std::vector<std::size_t>& tests) {
    for (std::size_t t = 0; t < std::min<std::size_t>(4, tests.size()); ++t) {
      const std::size_t k = tests[t];
      if (k < links)
        std::printf(" %s/scene", spheres.links()[k].c_str());
      else
        std::printf(" %s/%s", spheres.links()[pairs[k - links].first].c_str(),
                    spheres.links()[pairs[k - links].second].c_str());
    }
    std::printf("\n");
  };
  std::printf("pair tables: %zu of %zu self pairs, %.1f%% of their cells free\n",
              spheres.pair_tables(), pairs.size(), 100.0 * spheres.pair_tables_free());
  std::printf("test order (%zu samples): %zu tests, head %zu; first:",
              spheres.options().order_samples, order.tests.size(), order.head);
  first(order.tests);
  if (order.probe.empty()) {
    std::printf("bounds order: no probe; first:");
  } else {
    std::printf("bounds order: probe rounds ending at");
    for (std::size_t end : order.probe) std::printf(" %zu", end);
    std::printf(" of the tests; first:");
  }
  first(order.bounds_tests);
}

// The fallback as built, its tables, and the checker's sets and grid.
void print_checker_setup(const CheckerBenchInput& in, const fcl::CertifiedChecker& certified,
                         const RobotModel* fine, double build) {
  std::printf(
      "\ncertified fallback: %zu witnesses, %zu of %zu self pairs seen colliding in %zu "
      "samples (seed %u)\n",
      certified.fallback().witnesses().size(), certified.fallback().seen_colliding(),
      certified.fallback().self_pairs().size(), in.order_samples, in.order_seed);
  print_tables(certified, build);
  const check::RobotChecker& spheres = certified.spheres();
  const check::GridStats g = spheres.grid();
  std::printf(
      "\nrobot checker: planner sets %zu covering + %zu inner spheres, fine sets %zu + %zu; %s "
      "kernel; scene grid of %zu cells of %.3f m, %zu element entries, %zu elements; %zu of %zu "
      "links never near the scene; built in %.2f s; rounding allowance %.2g m\n",
      spheres_of(in.planner->model, true), spheres_of(in.planner->model, false),
      fine ? spheres_of(*fine, true) : 0, fine ? spheres_of(*fine, false) : 0,
      spheres.uses_avx2() ? "AVX2" : "scalar", g.cells, g.cell_side, g.entries, g.elements,
      g.far_links, spheres.links().size(), build, spheres.allowance());
  print_test_order(spheres);
}

// with_scene on the scene the checker has: the scene's own parts built, the robot's shared,
// timed against the whole build; its verdicts must be the checker's (else it throws).
void print_with_scene(const CheckerBenchInput& in, const fcl::CertifiedChecker& certified,
                      const std::vector<double>& q, double build) {
  const auto t0 = Clock::now();
  const fcl::CertifiedChecker moved = certified.with_scene(in.scene);
  const double seconds = seconds_since(t0);
  const std::size_t n = in.configs.size();
  std::vector<Verdict> a(n), b(n);
  certified.check(q.data(), n, a.data(), 0);
  moved.check(q.data(), n, b.data(), 0);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < n; ++i) differ += a[i] != b[i];
  std::printf(
      "certified checker with_scene (the same scene): built in %.3f s against %.2f s anew; %zu "
      "of %zu verdicts differ\n",
      seconds, build, differ, n);
  if (differ > 0) throw std::runtime_error("with_scene changed verdicts");
}

// The spheres mode's rows (learnt order, doubles, default order) and the bounds row.
void add_sphere_rows(const CheckerBenchInput& in, const check::CheckerOptions& o,
                     const RobotModel* fine, const check::RobotChecker& spheres,
                     const check::RobotChecker& unordered, const std::vector<double>& q,
                     std::vector<Row>& rows) {
  const std::size_t n = in.configs.size();
  std::vector<Verdict> v(n);
  for (int threads : {1, 0}) {
    if (threads != 1 && !in.all_cores) continue;
    Row r{"check/s", threads};
    const int repeats = threads == 1 && in.spheres_repeats > 0 ? in.spheres_repeats : in.repeats;
    r.micros =
        best_micros(repeats, threads != 1,
                    [&] { spheres.check(q.data(), n, check::Mode::spheres, v.data(), threads); }) /
        double(n);
    r.colliding = colliding_of(v);
    r.note = "planner covering sets only";
    rows.push_back(r);
  }
  {
    // The same checks with every test in doubles (no float pass): the float pass's gain.
    check::CheckerOptions od = o;
    od.float_tests = false;
    const check::RobotChecker doubles(in.planner->model, fcl::scene_from_fcl(in.scene).scene, od,
                                      fine);
    Row r{"check/d", 1};
    r.micros = best_micros(in.repeats, false,
                           [&] { doubles.check(q.data(), n, check::Mode::spheres, v.data(), 1); }) /
               double(n);
    r.colliding = colliding_of(v);
    r.note = "as check/s, every test in doubles";
    rows.push_back(r);
  }
  {
    Row r{"check/s0", 1};
    r.micros =
        best_micros(in.repeats, false,
                    [&] { unordered.check(q.data(), n, check::Mode::spheres, v.data(), 1); }) /
        double(n);
    r.colliding = colliding_of(v);
    r.note = "as check/s, the tests in their default order (order_samples 0)";
    rows.push_back(r);
  }
  {
    Row r{"bounds", 1};
    r.micros = best_micros(in.repeats, false,
                           [&] { spheres.check(q.data(), n, check::Mode::bounds, v.data(), 1); }) /
               double(n);
    r.colliding = colliding_of(v);
    const auto undecided = std::count(v.begin(), v.end(), Verdict::undecided);
    r.note = "no fallback: " + std::to_string(undecided) + " undecided, counted as colliding";
    rows.push_back(r);
  }
}

// A certified checker's row on one thread (best of `repeats`): its time, its verdicts in v,
// the fallback's stats of the last run.
Row certified_row(const char* name, const fcl::CertifiedChecker& c, int repeats,
                  const std::vector<double>& q, std::vector<Verdict>& v,
                  fcl::FallbackStats& stats) {
  Row r{name, 1};
  r.micros = best_micros(repeats, false,
                         [&] {
                           stats = {};
                           c.check(q.data(), v.size(), v.data(), 1, &stats);
                         }) /
             double(v.size());
  r.colliding = colliding_of(v);
  return r;
}

// The certified rows: the fallback as built, without the kernel's witnesses, without trees
// and order, one configuration at
// a time; and the same checks as a loop of FCL calls.
void add_certified_rows(const CheckerBenchInput& in, const check::CheckerOptions& o,
                        const RobotModel* fine, const fcl::FallbackOptions& fallback,
                        const fcl::CertifiedChecker& certified, const std::vector<double>& q,
                        std::vector<Row>& rows) {
  const check::RobotChecker& spheres = certified.spheres();
  const std::size_t n = in.configs.size();
  std::vector<Verdict> v(n);
  for (int threads : {1, 0}) {
    if (threads != 1 && !in.all_cores) continue;
    Row r{"check/c", threads};
    fcl::FallbackStats stats;
    r.micros = best_micros(in.repeats, threads != 1,
                           [&] {
                             stats = {};
                             certified.check(q.data(), n, v.data(), threads, &stats);
                           }) /
               double(n);
    r.colliding = colliding_of(v);
    char note[224];
    std::snprintf(note, sizeof note,
                  "certified: %zu colliding by tables first, %zu configurations (%.2f%%) to the "
                  "fallback, %zu by witnesses, %zu pairs by tables, %zu pairs, %zu by planes, %zu "
                  "to the meshes; %zu undecided",
                  stats.table_first, stats.configurations,
                  100.0 * double(stats.configurations) / double(n), stats.witnessed, stats.tabled,
                  stats.pairs, stats.planes, stats.meshes,
                  static_cast<std::size_t>(std::count(v.begin(), v.end(), Verdict::undecided)));
    r.note = note;
    rows.push_back(r);
  }
  // A row of the certified checker built with other fallback options, and its stats.
  fcl::FallbackStats stats;
  auto variant = [&](const char* name, const fcl::FallbackOptions& f) {
    const fcl::CertifiedChecker c(in.planner->model, fine, in.fine->meshes, in.scene, o, f);
    return certified_row(name, c, in.repeats, q, v, stats);
  };
  char note[160];
  if (in.order_samples > 0) {
    // The same without the witnesses in the kernel's inner sets: the fallback tests them.
    fcl::FallbackOptions f = fallback;
    f.kernel_witnesses = false;
    Row r = variant("check/cw-", f);
    std::snprintf(note, sizeof note,
                  "as check/c, the witnesses in the fallback only: %zu to the fallback, %zu by "
                  "witnesses, %zu to the meshes",
                  stats.configurations, stats.witnessed, stats.meshes);
    r.note = note;
    rows.push_back(r);
  }
  if (in.table_cells > 0) {
    // The same without the tables first, and both on the free configurations alone (those
    // of a planner's search, mostly): what the look-ups cost where they prove nothing.
    fcl::FallbackOptions f = fallback;
    f.tables_first = false;
    const fcl::CertifiedChecker c(in.planner->model, fine, in.fine->meshes, in.scene, o, f);
    Row r = certified_row("check/ct-", c, in.repeats, q, v, stats);
    std::snprintf(note, sizeof note, "as check/c, no tables first: %zu to the fallback",
                  stats.configurations);
    r.note = note;
    rows.push_back(r);
    std::vector<std::size_t> free;
    std::vector<double> qf;
    for (std::size_t i = 0; i < n; ++i)
      if (!in.reference[i]) {
        free.push_back(i);
        qf.insert(qf.end(), q.begin() + long(i * spheres.num_positions()),
                  q.begin() + long((i + 1) * spheres.num_positions()));
      }
    std::vector<Verdict> vf(free.size());
    for (const auto& [name, checker] : {std::pair{"check/cf", &certified}, {"check/cft-", &c}}) {
      Row rf = certified_row(name, *checker, in.repeats, qf, vf, stats);
      rf.subset = free;
      std::snprintf(note, sizeof note, "as check/c%s, the %zu free configurations only",
                    checker == &c ? "t-" : "", free.size());
      rf.note = note;
      rows.push_back(rf);
    }
  }
  {
    // The same without the separating planes: the meshes settle every pair left open.
    fcl::FallbackOptions f = fallback;
    f.separating_planes = false;
    Row r = variant("check/cp-", f);
    std::snprintf(note, sizeof note, "as check/c, no separating planes: %zu pairs to the meshes",
                  stats.meshes);
    r.note = note;
    rows.push_back(r);
  }
  if (in.trees || in.order_samples > 0) {
    // The same without the trees' sets and the learnt order: the fine sets as the sphere
    // trees, the bounds' order, no witnesses.
    Row r = variant("check/c-", fcl::FallbackOptions{});
    std::snprintf(note, sizeof note,
                  "as check/c, the fine sets as the trees, no order: %zu pairs, %zu to the meshes",
                  stats.pairs, stats.meshes);
    r.note = note;
    rows.push_back(r);
  }
  {
    // The certified mode as it ran before check_bounds(): the bounds batch, then each
    // undecided configuration alone (its bounds again, one to a block, then its pairs).
    Row r{"check/c1", 1};
    const std::size_t dof = spheres.num_positions();
    r.micros = best_micros(in.repeats, false,
                           [&] {
                             stats = {};
                             spheres.check(q.data(), n, check::Mode::bounds, v.data(), 1);
                             for (std::size_t i = 0; i < n; ++i)
                               if (v[i] == Verdict::undecided)
                                 v[i] = certified.check(q.data() + i * dof, &stats);
                           }) /
               double(n);
    r.colliding = colliding_of(v);
    r.note = "as check/c, each undecided configuration's bounds again alone";
    rows.push_back(r);
  }
  if (in.fcl_loop) {
    FclSphereLoop loop(in.planner->model, spheres, in.scene, in.margin, in.self);
    Row r{"fcl loop", 1};
    std::vector<char> c(n);
    r.micros = best_micros(1, false,
                           [&] {
                             for (std::size_t i = 0; i < n; ++i) c[i] = loop.collide(in.configs[i]);
                           }) /
               double(n);
    r.colliding = c;
    r.note = "the planner covering sets as fcl::Sphere, a loop of fcl::collide";
    rows.push_back(r);
  }
}

}  // namespace

void print_checker_rows(const CheckerBenchInput& in) {
  check::CheckerOptions o;
  o.margin = in.margin;
  o.disabled = in.disabled;
  o.self = in.self;
  o.order_seed = in.order_seed;
  o.max_cells = in.max_cells;
  const auto t0 = Clock::now();
  const RobotModel* fine = in.fine != in.planner ? &in.fine->model : nullptr;
  fcl::FallbackOptions fallback;
  fallback.trees = in.trees ? &in.trees->model : nullptr;
  fallback.order.samples = in.order_samples;
  fallback.order.margin = in.margin;
  fallback.order.seed = in.order_seed;
  fallback.table_cells = in.table_cells;
  fallback.table_pairs = in.table_pairs;
  fallback.table_store = in.table_store;
  const fcl::CertifiedChecker certified(in.planner->model, fine, in.fine->meshes, in.scene, o,
                                        fallback);
  const double build = seconds_since(t0);
  print_checker_setup(in, certified, fine, build);
  const std::vector<double> q = rows_of(in.configs);
  print_with_scene(in, certified, q, build);
  // The same checks with the tests in their default order (each link against the scene,
  // then each self pair), not the learnt one: the order's gain, side by side.
  check::CheckerOptions o0 = o;
  o0.order_samples = 0;
  const check::RobotChecker unordered(in.planner->model, fcl::scene_from_fcl(in.scene).scene, o0,
                                      fine);
  std::vector<Row> rows;
  add_sphere_rows(in, o, fine, certified.spheres(), unordered, q, rows);
  add_certified_rows(in, o, fine, fallback, certified, q, rows);
  std::printf("%-10s %7s %10s %10s %10s %10s %7s %7s  %s\n", "checker", "threads", "us/config",
              "ns/config", "vs exact", "colliding", "missed", "alarms", "note");
  for (const Row& r : rows) print_row(r, in);
  print_edges(in, certified, unordered);
}

}  // namespace medspheres::bench
