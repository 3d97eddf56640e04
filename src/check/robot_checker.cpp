#include "medspheres/check/robot_checker.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "medspheres/number_text.h"
#include "medspheres/sample_configurations.h"
#include "medspheres/threads.h"

#include "block.h"
#include "distance_field.h"
#include "float_sincos.h"
#include "link_reach.h"
#include "robot_layout.h"
#include "scene_grid.h"
#include "test_order.h"

namespace medspheres::check {
namespace detail {
namespace {

bool cpu_has_avx2() {
#if defined(MEDSPHERES_CHECK_AVX2)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

KernelFn choose_kernel(Simd simd) {
  const bool avx2 = cpu_has_avx2();
  if (simd == Simd::avx2 && !avx2)
    throw std::invalid_argument(
        "robot checker: AVX2 asked for, but this processor or build has none");
#if defined(MEDSPHERES_CHECK_AVX2)
  if (simd != Simd::scalar && avx2) return run_block_avx2;
#endif
  return run_block_scalar;
}

// The batch kernel of the same build as `kernel`.
BatchFn batch_kernel(KernelFn kernel) {
#if defined(MEDSPHERES_CHECK_AVX2)
  if (kernel == run_block_avx2) return run_batch_avx2;
#endif
  return kernel == run_block_scalar ? run_batch_scalar : nullptr;
}

// One thread's buffers for the kernel.
struct Workspace {
  std::vector<double> frames, q;
  std::vector<float> frames_f;
  std::unique_ptr<double[]> posed;
  std::unique_ptr<float[]> posed_f;
  std::vector<unsigned char> flags, near, pending, unsure;
  std::vector<int> lists;
  std::vector<UndecidedPair>* pairs[kLanes] = {};
};

// A layout's spheres and bounding spheres in precision T, and the grid's view in T.
template <class T>
struct SphereArrays {
  std::vector<T> x, y, z, r, bound, pair_reach2;
  KernelSpheres<T> view(const SceneGrid& g, const DistanceField& f) const {
    KernelSpheres<T> k;
    k.x = x.data();
    k.y = y.data();
    k.z = z.data();
    k.r = r.data();
    k.bound = bound.data();
    k.pair_reach2 = pair_reach2.data();
    if (!f.empty()) {
      for (int d = 0; d < 3; ++d) {
        k.grid.origin[d] = T(f.origin()[d]);
        k.grid.n[d] = f.dims()[d];
      }
      k.grid.side = T(f.cell_side());
      k.grid.inverse_side = T(1.0 / f.cell_side());
      k.grid.field = f.bounds();
      k.grid.unit = T(f.unit());
      k.grid.pad = T(g.pad());
      for (int d = 0; d < 3; ++d) {
        k.grid.box_min[d] = T(g.bounds().min()[d]);
        k.grid.box_max[d] = T(g.bounds().max()[d]);
      }
    }
    return k;
  }
};

template <class T>
SphereArrays<T> sphere_arrays(const RobotLayout& l) {
  SphereArrays<T> a;
  a.x.assign(l.x.begin(), l.x.end());
  a.y.assign(l.y.begin(), l.y.end());
  a.z.assign(l.z.begin(), l.z.end());
  a.r.assign(l.r.begin(), l.r.end());
  for (const LinkLayout& link : l.links) a.bound.insert(a.bound.end(), link.bound, link.bound + 4);
  return a;
}

// KernelSpheres::pair_reach2 of the arrays a (slack: 0 in doubles).
template <class T>
void set_pair_reach(SphereArrays<T>& a, const RobotLayout& l, double margin, double allowance,
                    T slack) {
  a.pair_reach2.resize(l.pair_a.size());
  for (std::size_t k = 0; k < l.pair_a.size(); ++k) {
    const T reach = T(double(a.bound[4 * l.pair_a[k] + 3]) + double(a.bound[4 * l.pair_b[k] + 3]) +
                      margin + allowance) +
                    slack;
    a.pair_reach2[k] = reach * reach;
  }
}

}  // namespace
}  // namespace detail

struct RobotChecker::Impl {
  CheckerOptions options;
  detail::RobotLayout layout;
  std::unique_ptr<detail::SceneGrid> grid;
  std::unique_ptr<detail::DistanceField> field;
  // The robot's models, kept for with_scene().
  std::shared_ptr<const RobotModel> planner_model, fine_model;
  // kernel_robot.table, shared by the checkers with_scene() makes; built for pairs farther
  // apart than table_threshold (pair_table.h), at least the margin and this checker's
  // allowance.
  std::shared_ptr<const detail::PairTables> tables;
  double table_threshold = 0.0;
  detail::SphereArrays<double> spheres_d;
  detail::SphereArrays<float> spheres_f;
  std::vector<unsigned char> far;  // kernel_robot.far
  detail::KernelRobot kernel_robot;
  detail::KernelFn kernel = nullptr;
  detail::BatchFn batch_kernel = nullptr;   // kernel's build
  std::vector<std::uint32_t> order;         // kernel_robot.order
  std::vector<std::uint32_t> bounds_order;  // kernel_robot.bounds_order
  // The bounds mode's probe (block.h) in rounds: round r runs bounds_order's tests
  // [probe[r - 1], probe[r]) (from 0 in round 0) on the lanes the rounds before left open,
  // regrouped (probed_bounds); empty: no probe.
  std::vector<int> probe;
  double allowance = 0.0;
  float slack = 0.0f;
  // Per joint position: the largest |q| for which the float tests' slack holds
  // (float_ranges).
  std::vector<double> float_range;
  std::size_t scene_objects = 0;

  // Everything but options and the models (set first) for \p scene; the pair tables taken
  // from \p donor (a checker of the same robot and options) when they hold here.
  void build(const Scene& scene, const Impl* donor);
  void share_or_build_tables(const Impl* donor);

  // The calling thread's workspace, kept between calls for the checker that used it last
  // (`id`): the one-configuration, one-edge and any_colliding calls that a planner makes by
  // the million allocate nothing. The caller leaves no pointer of its own in it.
  detail::Workspace& thread_workspace() const;
  const std::uint64_t id = next_checker_id();

  static std::uint64_t next_checker_id() {
    static std::atomic<std::uint64_t> next{1};
    return next++;
  }

  detail::Workspace workspace() const {
    detail::Workspace w;
    const std::size_t frames = static_cast<std::size_t>(layout.frames) * 12;
    w.frames.assign(2 * frames * detail::kHalf, 0.0);
    for (int h = 0; h < 2; ++h)
      for (int e : {0, 4, 8})
        for (int l = 0; l < detail::kHalf; ++l)
          w.frames[h * frames * detail::kHalf + e * detail::kHalf + l] = 1.0;  // frame 0: W
    w.frames_f.assign(frames * detail::kLanes, 0.0f);
    for (int e : {0, 4, 8})
      for (int l = 0; l < detail::kLanes; ++l) w.frames_f[e * detail::kLanes + l] = 1.0f;
    // The posed points are written before they are read (posed_flag): left uninitialised,
    // so that a workspace for one configuration or one edge costs no fill of its size.
    const std::size_t points = layout.x.size() + layout.links.size();
    w.posed.reset(new double[points * 3 * detail::kHalf]);
    w.posed_f.reset(new float[points * 3 * detail::kLanes]);
    w.flags.assign(layout.links.size() * detail::kSlots, 0);
    w.near.assign(layout.x.size(), 0);
    w.lists.assign(layout.links.size(), 0);
    w.pending.assign(layout.links.size() + layout.pair_a.size(), 0);
    w.unsure.assign(layout.links.size() + layout.pair_a.size(), 0);
    w.q.assign(layout.dof * detail::kLanes, 0.0);
    return w;
  }

  // Whether the float tests' slack holds for the block's configurations.
  bool floats_hold(const std::vector<double>& q) const {
    for (std::size_t j = 0; j < layout.dof; ++j)
      for (int l = 0; l < detail::kLanes; ++l)
        if (std::abs(q[j * detail::kLanes + std::size_t(l)]) > float_range[j]) return false;
    return true;
  }

  void validate(const double* q, std::size_t index) const {
    for (std::size_t j = 0; j < layout.dof; ++j)
      if (!std::isfinite(q[j]) || std::abs(q[j]) > 1e6)
        throw std::invalid_argument("robot checker: configuration " + std::to_string(index) +
                                    ": the position of joint \"" + layout.joint_names[j] +
                                    "\" is not finite or beyond 1e6");
  }

  // check() and check_bounds() (with `undecided`) of n configurations.
  void batch(const double* q, std::size_t n, Mode mode, Verdict* out,
             std::vector<UndecidedPair>* undecided, int threads) const;
  // The block of configurations q (kLanes, lanes `lanes` real) on w's buffers, not run.
  detail::Block block(detail::Workspace& w, const std::vector<double>& q, unsigned lanes, Mode mode,
                      std::uint32_t* hits, int probe_from, int probe_to) const;
  // Runs the kernel on w.q (kLanes configurations, lanes `lanes` real); with `hits`, a
  // learning run (block.h), in doubles; `probe_from`, `probe_to`: a probe (block.h).
  detail::Block run(detail::Workspace& w, unsigned lanes, Mode mode, bool want_pairs,
                    std::uint32_t* hits = nullptr, int probe_from = 0, int probe_to = 0) const;
  // Mode::spheres of n configurations in batches of blocks (block.h, Batch).
  void spheres_batches(const double* q, std::size_t n, Verdict* out, int threads) const;
  // Mode::bounds by probe and regrouping (batch), with `undecided` (may be null) each
  // configuration's undecided pairs; false when the checker has no probe.
  bool probed_bounds(const double* q, std::size_t n, Verdict* out,
                     std::vector<UndecidedPair>* undecided, int threads) const;
  // Sets `order` from options.order_samples configurations of `planner`.
  void learn_order(const RobotModel& planner);
  // The kernel on w.q's lanes `lanes`, in the spheres mode stopping at the first lane found
  // colliding (Block::any): colliding is not empty exactly when some lane collides.
  detail::Block run_any(detail::Workspace& w, unsigned lanes, Mode mode) const;
  // One edge in rake order (robot_checker.h); `checked` counts the samples run.
  Verdict edge(detail::Workspace& w, const double* q0, const double* q1, double resolution,
               Mode mode, std::vector<double>* undecided_t, std::size_t& checked) const;
};

namespace {

void check_resolution(double resolution) {
  if (!std::isfinite(resolution) || resolution <= 0.0)
    throw std::invalid_argument("robot checker: the edge resolution must be finite and > 0, got " +
                                number_text(resolution));
}

// The n of an edge (robot_checker.h), checked: a resolution that is not finite and > 0, or
// that would give more than kMaxEdgeSteps configurations, is refused (\p edge: its index).
std::size_t steps_of(const double* q0, const double* q1, std::size_t dof, double resolution,
                     std::size_t edge) {
  check_resolution(resolution);
  double s = 0.0;
  for (std::size_t j = 0; j < dof; ++j) s += (q1[j] - q0[j]) * (q1[j] - q0[j]);
  const double n = std::ceil(std::sqrt(s) / resolution);
  if (!(n <= double(kMaxEdgeSteps)))
    throw std::invalid_argument("robot checker: edge " + std::to_string(edge) + " is " +
                                number_text(std::sqrt(s)) + " long: the resolution " +
                                number_text(resolution) + " would check more than " +
                                std::to_string(kMaxEdgeSteps) + " configurations on it");
  return std::max<std::size_t>(1, static_cast<std::size_t>(n));
}

// The objects near a lane's posed covering spheres (the last level's), or every object
// when the link has no covering set; in the float pass, also those within its slack more.
void scene_objects(const detail::RobotLayout& layout, const detail::SceneGrid& grid,
                   const detail::Block& b, int lane, int link, std::vector<std::uint32_t>& out) {
  const detail::LinkLayout& l = layout.links[static_cast<std::size_t>(link)];
  const int slot =
      layout.fine && l.count[detail::kFineOuter] > 0 ? detail::kFineOuter : detail::kOuter;
  if (l.count[slot] == 0) {
    out.push_back(UINT32_MAX);
    return;
  }
  // The float pass's posed points (b.half < 0) lie within the slack of the double ones.
  const bool floats = b.half < 0;
  const double reach = b.margin + b.allowance + (floats ? double(b.slack) : 0.0);
  for (std::uint32_t i = l.begin[slot]; i < l.begin[slot] + l.count[slot]; ++i) {
    double p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = floats ? double(b.posed_f[(3 * i + k) * detail::kLanes + lane])
                    : b.posed[(3 * i + k) * detail::kHalf + lane];
    grid.objects_within(p, layout.r[i] + reach, out);
  }
}

struct SinkContext {
  const detail::RobotLayout* layout;
  const detail::SceneGrid* grid;
  std::size_t scene_objects;
  detail::Workspace* w;
};

// The sink: `lane` is a lane of the half b.half, or of the block (the float pass, b.half -1).
void record_pair(detail::Block& b, int lane, int link, int other) {
  const auto* c = static_cast<const SinkContext*>(b.context);
  std::vector<UndecidedPair>* pairs = c->w->pairs[std::max(b.half, 0) * detail::kHalf + lane];
  if (pairs == nullptr) return;
  if (other >= 0) {
    pairs->push_back({std::size_t(link), std::size_t(other), true});
    return;
  }
  std::vector<std::uint32_t> objects;
  scene_objects(*c->layout, *c->grid, b, lane, link, objects);
  std::sort(objects.begin(), objects.end());
  objects.erase(std::unique(objects.begin(), objects.end()), objects.end());
  if (!objects.empty() && objects.back() == UINT32_MAX) {  // every object
    objects.clear();
    for (std::size_t o = 0; o < c->scene_objects; ++o)
      objects.push_back(static_cast<std::uint32_t>(o));
  }
  for (std::uint32_t o : objects) pairs->push_back({std::size_t(link), std::size_t(o), false});
}

}  // namespace

detail::Block RobotChecker::Impl::block(detail::Workspace& w, const std::vector<double>& q,
                                        unsigned lanes, Mode mode, std::uint32_t* hits,
                                        int probe_from, int probe_to) const {
  detail::Block b;
  b.q = q.data();
  b.lanes = lanes;
  b.bounds = mode == Mode::bounds;
  b.self = options.self;
  b.floats = options.float_tests && hits == nullptr && floats_hold(q);
  b.hits = hits;
  b.probe_from = probe_from;
  b.probe = mode == Mode::bounds ? probe_to : 0;
  b.margin = options.margin;
  b.allowance = allowance;
  b.slack = slack;
  b.frames = w.frames.data();
  b.frames_f = w.frames_f.data();
  b.posed = w.posed.get();
  b.posed_f = w.posed_f.get();
  b.posed_flag = w.flags.data();
  b.near = w.near.data();
  b.lists = w.lists.data();
  b.pending = w.pending.data();
  b.unsure = w.unsure.data();
  return b;
}

detail::Block RobotChecker::Impl::run(detail::Workspace& w, unsigned lanes, Mode mode,
                                      bool want_pairs, std::uint32_t* hits, int probe_from,
                                      int probe_to) const {
  detail::Block b = block(w, w.q, lanes, mode, hits, probe_from, probe_to);
  // The sink sees the undecided lanes of the float pass whose tests were certain, and the
  // double pass.
  SinkContext context{&layout, grid.get(), scene_objects, &w};
  if (want_pairs) {
    b.sink = record_pair;
    b.context = &context;
  }
  kernel(kernel_robot, *grid, b);
  b.sink = nullptr;
  b.context = nullptr;
  return b;
}

detail::Workspace& RobotChecker::Impl::thread_workspace() const {
  struct Cached {
    std::uint64_t owner = 0;
    detail::Workspace w;
  };
  thread_local Cached cached;
  if (cached.owner != id) {
    cached.w = workspace();
    cached.owner = id;
  }
  return cached.w;
}

detail::Block RobotChecker::Impl::run_any(detail::Workspace& w, unsigned lanes, Mode mode) const {
  detail::Block b = block(w, w.q, lanes, mode, nullptr, 0, 0);
  b.any = mode == Mode::spheres;
  kernel(kernel_robot, *grid, b);
  return b;
}

Verdict RobotChecker::Impl::edge(detail::Workspace& w, const double* q0, const double* q1,
                                 double resolution, Mode mode, std::vector<double>* undecided_t,
                                 std::size_t& checked) const {
  const std::size_t n = steps_of(q0, q1, layout.dof, resolution, 0);
  const std::size_t run = (n + 1 + detail::kLanes - 1) / detail::kLanes;  // samples per lane
  bool undecided = false;
  for (std::size_t step = 0; step < run; ++step) {
    unsigned lanes = 0;
    std::size_t k[detail::kLanes];
    for (int l = 0; l < detail::kLanes; ++l) {
      k[l] = std::size_t(l) * run + step;
      if (k[l] <= n) lanes |= 1u << l;
      if (k[l] > n) k[l] = n;  // an idle lane repeats the last sample
      const double t = double(k[l]) / double(n);
      for (std::size_t j = 0; j < layout.dof; ++j)
        w.q[j * detail::kLanes + std::size_t(l)] = q0[j] + t * (q1[j] - q0[j]);
    }
    const detail::Block b = run_any(w, lanes, mode);
    for (int l = 0; l < detail::kLanes; ++l) checked += lanes >> l & 1;
    if (b.colliding & lanes) return Verdict::colliding;
    for (int l = 0; l < detail::kLanes; ++l)
      if (b.undecided >> l & lanes >> l & 1) {
        undecided = true;
        if (undecided_t) undecided_t->push_back(double(k[l]) / double(n));
      }
  }
  return undecided ? Verdict::undecided : Verdict::free;
}

namespace {

// Rounding allowance: the distances compared are sums and products of coordinates of at
// most `extent` metres over chains of at most `depth` joints; their rounding is below
// 64 (depth + 8) eps extent, which 1e-9 (1 + extent) exceeds by over 10^4 for any robot of
// fewer than 100 joints.
// The scene's largest coordinate, with every object's size.
double scene_extent(const Scene& scene) {
  double extent = 0.0;
  for (const SceneObject& o : scene.objects()) {
    extent = std::max(
        extent, o.X_WO.translation().cwiseAbs().maxCoeff() + o.size.norm() + o.radius + o.length);
    for (const Eigen::Vector3d& p : o.points) extent = std::max(extent, p.cwiseAbs().maxCoeff());
    for (const Eigen::Vector3d& v : o.mesh.vertices)
      extent = std::max(extent, (o.X_WO * v).cwiseAbs().maxCoeff());
  }
  return extent;
}

double rounding_allowance(const detail::RobotLayout& layout, const Scene& scene) {
  double extent = layout.extent;
  for (const detail::FrameStep& s : layout.steps)
    extent += std::sqrt(s.u[0] * s.u[0] + s.u[1] * s.u[1] + s.u[2] * s.u[2]) +
              std::sqrt(s.v[0] * s.v[0] + s.v[1] * s.v[1] + s.v[2] * s.v[2]);
  return 1e-9 * (1.0 + std::max(extent, scene_extent(scene)));
}

// Per joint position, the largest |q| the float tests' slack is computed for: for a joint
// that moves a prismatic joint, the larger of 1 and its limits' magnitudes; for one that
// turns a revolute joint, as far as its angle stays below 2^26 (where the reduction by
// pi / 2 is exact: float_sincos.h's bound needs it); unbounded otherwise.
std::vector<double> float_ranges(const RobotModel& model, const detail::RobotLayout& layout) {
  std::vector<double> out(layout.dof, std::numeric_limits<double>::infinity());
  for (const detail::FrameStep& s : layout.steps) {
    double& range = out[static_cast<std::size_t>(s.source)];
    if (!s.prismatic) {
      if (s.multiplier != 0.0)
        range =
            std::min(range, (std::ldexp(1.0, 26) - std::abs(s.offset)) / std::abs(s.multiplier));
      continue;
    }
    const Joint* j = model.find_joint(layout.joint_names[static_cast<std::size_t>(s.source)]);
    double limit = 1.0;
    if (j != nullptr && j->limits)
      limit = std::max({limit, std::abs(j->limits->lower), std::abs(j->limits->upper)});
    range = std::min(range, limit);
  }
  return out;
}

// The largest |P|_F + |C|_F + |S|_F of a revolute step (Frobenius norms): 1 + 2 sqrt 2
// for a rotation about a unit axis.
double largest_rotation_sum(const detail::RobotLayout& layout) {
  double largest = 0.0;
  for (const detail::FrameStep& s : layout.steps) {
    if (s.prismatic) continue;
    double p = 0.0, c = 0.0, r = 0.0;
    for (int e = 0; e < 9; ++e) {
      p += s.P[e] * s.P[e];
      c += s.C[e] * s.C[e];
      r += s.S[e] * s.S[e];
    }
    largest = std::max(largest, std::sqrt(p) + std::sqrt(c) + std::sqrt(r));
  }
  return largest;
}

// The longest chain of moving frames from W (steps are ordered parents first).
int chain_depth(const detail::RobotLayout& layout) {
  std::vector<int> depth(static_cast<std::size_t>(layout.frames), 0);
  int deepest = 0;
  for (const detail::FrameStep& s : layout.steps) {
    const int d = depth[static_cast<std::size_t>(s.parent)] + 1;
    depth[static_cast<std::size_t>(s.frame)] = d;
    deepest = std::max(deepest, d);
  }
  return deepest;
}

// The float tests' slack: 2^-16 (1 + E) (1 + K d / 256), E bounding every coordinate and
// distance they handle (the robot's reach with its prismatic joints at float_ranges, the
// scene, the grid's corners), d the longest chain of moving frames, K = max(64, 4a +
// 12.02), a below (a = 36.0 and K = 156 for rotations about unit axes); u = 2^-24.
// - A step's float transform against its double one: a prismatic step's is the double one
//   rounded, its rotation within sqrt(3) u (Frobenius norm); a revolute step's rotation
//   is P + cos C + sin S in floats (the constants rounded, two products, two sums:
//   gamma_4 of |P| + |C| + |S| per entry) with a float sine and cosine within
//   kFloatSinCosError (3 u) + 2^-50 of the double ones (float_sincos.h: the same reduced
//   angle; the double polynomials are within 2^-50), so within 7.02 u (|P| + |C| + |S|)
//   per entry, 7.02 u s in norm, s = largest_rotation_sum (1 + 2 sqrt 2 for a rotation
//   about a unit axis). Let a = 9.1 + max(1.74, 7.02 s).
// - Float forward kinematics against the double one: a float product of two frames rounds
//   by at most gamma_3 |A| |B| per entry (at most 9.1 u in norm for rotations), so the
//   rotations of chain step k differ by e_k <= (1 + a u) e_(k-1) + a u (the step's float
//   rotation has norm <= 1 + a u), e_d <= a u d (1 + a u)^d <= (a + 1) u d for d < 6000;
//   the translations by f_k <= f_(k-1) + e_(k-1) |t_k| + u |t_k| + 4.01 u (1.74 |t_k| +
//   |p_(k-1)|), with sum |t_k| and |p| at most E: f_d <= ((a + 5.01) d + 8) u E. A posed
//   point x (|x| <= E) then lies within e_d |x| + f_d <= ((2a + 6.01) d + 8) u E of the
//   point posed on the double frame.
// - That frame's posed point lies within 12 u E of its double twin (three products and
//   three sums), a float squared distance compared with a float threshold errs by at most
//   14 u E more, and the grid's float cell look-up by 10 u E.
// Every certain float answer holds in doubles while the slack exceeds twice the sum,
// 2 (12 + 14 + 10 + 8 + (2a + 6.01) d) u E = (88 + (4a + 12.02) d) u E; it is
// (256 + K d) u (1 + E) with K >= 4a + 12.02.
float float_slack(const detail::RobotLayout& layout, const Scene& scene,
                  const detail::SceneGrid& grid, const std::vector<double>& range) {
  double reach = layout.extent;
  for (const detail::FrameStep& s : layout.steps) {
    const double travel = s.prismatic
                              ? std::abs(s.multiplier) * range[static_cast<std::size_t>(s.source)] +
                                    std::abs(s.offset)
                              : 0.0;
    reach += std::sqrt(s.u[0] * s.u[0] + s.u[1] * s.u[1] + s.u[2] * s.u[2]) +
             travel * std::sqrt(s.v[0] * s.v[0] + s.v[1] * s.v[1] + s.v[2] * s.v[2]);
  }
  double e = reach + scene_extent(scene);
  if (!grid.empty())
    for (int k = 0; k < 3; ++k)
      e = std::max(e, std::abs(grid.origin()[k]) + grid.dims()[k] * grid.cell_side());
  // In units of u: a revolute step's float rotation per entry of |P| + |C| + |S| (gamma_4
  // with the sine's growth, and the sine's bound), a, and K.
  const double entry = 4.01 + std::ldexp(detail::kFloatSinCosError, 24) + 0.01;
  const double a = 9.1 + std::max(1.74, entry * largest_rotation_sum(layout));
  const double k = std::max(64.0, 4.0 * a + 12.02);
  const double slack = std::ldexp(1.0 + e, -16) * (1.0 + k * chain_depth(layout) / 256.0);
  return std::nextafter(static_cast<float>(slack), std::numeric_limits<float>::infinity());
}

}  // namespace

RobotChecker::RobotChecker(const RobotModel& planner, const Scene& scene,
                           const CheckerOptions& options, const RobotModel* fine)
    : impl_(std::make_unique<Impl>()) {
  if (!std::isfinite(options.margin) || options.margin < 0.0)
    throw std::invalid_argument("robot checker: the margin must be finite and >= 0");
  if (!options.X_WB.matrix().allFinite())
    throw std::invalid_argument("robot checker: the base pose is not finite");
  if (const std::string problem = threads_problem(options.build_threads); !problem.empty())
    throw std::invalid_argument("robot checker: build_threads " + problem);
  Impl& m = *impl_;
  m.options = options;
  m.planner_model = std::make_shared<const RobotModel>(planner);
  if (fine) m.fine_model = std::make_shared<const RobotModel>(*fine);
  m.build(scene, nullptr);
}

RobotChecker::RobotChecker(const RobotChecker& donor, const Scene& scene)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = donor.impl_->options;
  m.planner_model = donor.impl_->planner_model;
  m.fine_model = donor.impl_->fine_model;
  m.build(scene, donor.impl_.get());
}

RobotChecker RobotChecker::with_scene(const Scene& scene) const {
  return RobotChecker(*this, scene);
}

// Tables built beyond the margin and at least kTableAllowance: valid for any checker of the
// robot whose allowance is at most that (a scene and robot within about 1 km of the origin,
// robot_checker.cpp's rounding_allowance), so with_scene() shares them; 1 um more than the
// allowance the tables need costs a negligible share of free cells.
constexpr double kTableAllowance = 1e-6;

void RobotChecker::Impl::share_or_build_tables(const Impl* donor) {
  const double needed = options.margin + allowance;
  if (donor && donor->table_threshold >= needed) {
    tables = donor->tables;
    table_threshold = donor->table_threshold;
    return;
  }
  table_threshold = options.margin + std::max(allowance, kTableAllowance);
  tables = std::make_shared<const detail::PairTables>(*planner_model, layout, table_threshold,
                                                      options.self ? options.pair_table_cells : 0);
}

void RobotChecker::Impl::build(const Scene& scene, const Impl* donor) {
  const RobotModel& planner = *planner_model;
  kernel = detail::choose_kernel(options.simd);
  batch_kernel = detail::batch_kernel(kernel);
  layout = detail::make_layout(planner, fine_model.get(), options.X_WB, options.disabled,
                               options.inner_points);
  allowance = rounding_allowance(layout, scene);
  scene_objects = scene.size();
  // One cell's list answers balls up to the radius of three in four spheres (the models'
  // own: the inner points leave the grid as it was); larger ones read a few cells
  // (scene_grid.h): short lists for the many, no miss for the few.
  std::vector<double> radii = layout.r;
  std::sort(radii.begin(), radii.end());
  for (const auto& [link, points] : options.inner_points)
    for (const Sphere& p : points)
      radii.erase(std::lower_bound(radii.begin(), radii.end(), p.radius));
  const double typical = radii.empty() ? 0.0 : radii[radii.size() * 3 / 4];
  const double reach = typical + options.margin + 2 * allowance;
  grid = std::make_unique<detail::SceneGrid>(scene, std::max(reach, 1e-6), options.cell,
                                             options.max_cells, allowance, options.build_threads);
  const detail::SceneGrid& g = *grid;
  spheres_d = detail::sphere_arrays<double>(layout);
  spheres_f = detail::sphere_arrays<float>(layout);
  detail::KernelRobot& k = kernel_robot;
  const detail::RobotLayout& l = layout;
  k.dof = static_cast<int>(l.dof);
  k.frames = l.frames;
  k.steps = static_cast<int>(l.steps.size());
  k.step = l.steps.data();
  k.links = static_cast<int>(l.links.size());
  k.link = l.links.data();
  k.spheres = static_cast<int>(l.x.size());
  field = std::make_unique<detail::DistanceField>(g, 2, options.build_threads);
  k.pairs = static_cast<int>(l.pair_a.size());
  k.pair_a = l.pair_a.data();
  k.pair_b = l.pair_b.data();
  // Beyond the margin by four allowances: more than the rounding of any test (and of the
  // reach's own sums) can take back, so a skipped test is one that would find the link clear.
  far = detail::links_far_from_scene(l, g, options.margin + 4 * allowance);
  k.far = far.data();
  k.fine = l.fine;
  share_or_build_tables(donor);
  k.table = tables->tables() > 0 ? tables->views().data() : nullptr;
  k.table_slots = static_cast<int>(tables->slots().size());
  k.table_slot = tables->slots().data();
  float_range = float_ranges(planner, l);
  slack = float_slack(l, scene, g, float_range);
  detail::set_pair_reach(spheres_d, l, options.margin, allowance, 0.0);
  detail::set_pair_reach(spheres_f, l, options.margin, allowance, slack);
  k.d = spheres_d.view(g, *field);
  k.f = spheres_f.view(g, *field);
  learn_order(planner);
}

RobotChecker::~RobotChecker() = default;
RobotChecker::RobotChecker(RobotChecker&&) noexcept = default;
RobotChecker& RobotChecker::operator=(RobotChecker&&) noexcept = default;

std::size_t RobotChecker::num_positions() const noexcept {
  return impl_->layout.dof;
}
const std::vector<std::string>& RobotChecker::joint_names() const noexcept {
  return impl_->layout.joint_names;
}
const std::vector<std::string>& RobotChecker::links() const noexcept {
  return impl_->layout.link_names;
}
std::vector<std::pair<std::size_t, std::size_t>> RobotChecker::self_pairs() const {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t k = 0; k < impl_->layout.pair_a.size(); ++k)
    out.emplace_back(impl_->layout.pair_a[k], impl_->layout.pair_b[k]);
  return out;
}
const CheckerOptions& RobotChecker::options() const noexcept {
  return impl_->options;
}
bool RobotChecker::uses_avx2() const noexcept {
  return impl_->kernel != detail::run_block_scalar;
}
double RobotChecker::allowance() const noexcept {
  return impl_->allowance;
}
TestOrder RobotChecker::test_order() const {
  TestOrder out;
  out.tests.assign(impl_->order.begin(), impl_->order.end());
  out.head = static_cast<std::size_t>(impl_->kernel_robot.head);
  out.bounds_tests.assign(impl_->bounds_order.begin(), impl_->bounds_order.end());
  out.probe.assign(impl_->probe.begin(), impl_->probe.end());
  return out;
}
std::size_t RobotChecker::pair_tables() const noexcept {
  return impl_->tables->tables();
}
double RobotChecker::pair_tables_free() const noexcept {
  return impl_->tables->free_share();
}
GridStats RobotChecker::grid() const noexcept {
  const detail::SceneGrid& g = *impl_->grid;
  std::size_t far = 0;
  for (unsigned char f : impl_->far) far += f;
  return {g.cell_side(), g.num_cells(), g.num_entries(), g.num_elements(), far};
}

namespace {

Verdict verdict_of(const detail::Block& b, int lane) {
  if (b.colliding >> lane & 1) return Verdict::colliding;
  return (b.undecided >> lane & 1) ? Verdict::undecided : Verdict::free;
}

// Lane l of the block takes configuration rows[first + l], or with `index`
// rows[index[first + l]] (the last real one repeated beyond n).
void fill_block(std::vector<double>& q, const double* rows, std::size_t first, std::size_t n,
                std::size_t dof, const std::size_t* index = nullptr) {
  for (int l = 0; l < detail::kLanes; ++l) {
    std::size_t i = std::min(first + std::size_t(l), n - 1);
    if (index) i = index[i];
    for (std::size_t j = 0; j < dof; ++j)
      q[j * detail::kLanes + std::size_t(l)] = rows[i * dof + j];
  }
}

}  // namespace

// The tests' hits over the sampled configurations, in doubles, every test in every lane:
// in the spheres mode the order by them (test_order.h) and the head of tests run before the
// links' bounding spheres against the scene; in the bounds mode (the tests' proofs) the
// bounds order and its probe. Changes no verdict.
void RobotChecker::Impl::learn_order(const RobotModel& planner) {
  const std::size_t tests = layout.links.size() + layout.pair_a.size();
  std::vector<std::uint32_t> hits(tests, 0), proofs(tests, 0);
  const std::size_t n = options.order_samples, dof = layout.dof;
  order = bounds_order = detail::order_by_hits(hits);  // the default orders while learning
  kernel_robot.order = order.data();
  kernel_robot.bounds_order = bounds_order.data();
  probe.clear();
  if (n == 0) return;
  std::vector<double> q;
  for (const Eigen::VectorXd& x :
       sample_configurations(planner, layout.joint_names, n, options.order_seed))
    q.insert(q.end(), x.data(), x.data() + x.size());
  detail::Workspace w = workspace();
  for (std::size_t first = 0; first < n; first += detail::kLanes) {
    fill_block(w.q, q.data(), first, n, dof);
    const std::size_t count = std::min<std::size_t>(detail::kLanes, n - first);
    run(w, (1u << count) - 1, Mode::spheres, false, hits.data());
    run(w, (1u << count) - 1, Mode::bounds, false, proofs.data());
  }
  order = detail::order_by_hits(hits);
  kernel_robot.order = order.data();
  bounds_order = detail::order_by_hits(proofs);
  kernel_robot.bounds_order = bounds_order.data();
  // The head: the leading tests that each found at least a quarter of the samples
  // colliding (block.h).
  int head = 0;
  while (std::size_t(head) < tests && 4 * std::size_t(hits[order[head]]) >= n) ++head;
  kernel_robot.head = head;
  // The probe's rounds: round r's tests end where the bounds order's tests prove fewer
  // than 8^-(r + 1) of the samples colliding; a round is kept while it proves at least half
  // of the samples it sees colliding (else the lanes it leaves open cost more run again
  // than the ones it decides spare).
  std::vector<std::size_t> rest(n);
  for (std::size_t i = 0; i < n; ++i) rest[i] = i;
  int from = 0;
  for (std::size_t share = 8; share <= 512 && !rest.empty(); share *= 8) {
    int to = from;
    while (std::size_t(to) < tests && share * std::size_t(proofs[bounds_order[to]]) >= n) ++to;
    if (to == from) continue;
    std::vector<std::size_t> open;
    for (std::size_t first = 0; first < rest.size(); first += detail::kLanes) {
      fill_block(w.q, q.data(), first, rest.size(), dof, rest.data());
      const std::size_t count = std::min<std::size_t>(detail::kLanes, rest.size() - first);
      const detail::Block b = run(w, (1u << count) - 1, Mode::bounds, false, nullptr, from, to);
      for (std::size_t l = 0; l < count; ++l)
        if (!(b.colliding >> l & 1)) open.push_back(rest[first + l]);
    }
    if (2 * (rest.size() - open.size()) < rest.size()) break;
    probe.push_back(to);
    rest = open;
    from = to;
  }
}

// The bounds mode in rounds. Each of the probe's rounds (block.h) runs on blocks of kLanes
// configurations: its tests of the bounds order (those that most often prove a collision
// first), at the planner's level, in floats; a lane they prove colliding is done (the whole
// run would prove it by the same test). The lanes left open are regrouped, kLanes to a
// block, for the next round, and at last run whole: a block's
// cost hardly depends on how many of its lanes are open, so a lane that is free or
// undecided no longer holds seven decided lanes' worth of tests. Each configuration's
// verdict is that of its own run (the kernel's lanes are independent). With `undecided`
// (check_bounds()), the last round's runs give each configuration's undecided pairs (the
// probe's rounds decide colliding lanes only, which have none).
bool RobotChecker::Impl::probed_bounds(const double* q, std::size_t n, Verdict* out,
                                       std::vector<UndecidedPair>* undecided, int threads) const {
  if (probe.empty() || n <= std::size_t(detail::kLanes)) return false;
  const std::size_t dof = layout.dof;
  if (undecided)
    for (std::size_t i = 0; i < n; ++i) undecided[i].clear();
  std::vector<std::size_t> rest(n);
  for (std::size_t i = 0; i < n; ++i) rest[i] = i;
  std::vector<unsigned char> open(n, 1);
  for (std::size_t r = 0; r <= probe.size(); ++r) {
    const std::size_t m = rest.size();
    const auto blocks = static_cast<long>((m + detail::kLanes - 1) / detail::kLanes);
    const bool whole = r == probe.size();
    const int from = r == 0 || whole ? 0 : probe[r - 1], to = whole ? 0 : probe[r];
#pragma omp parallel num_threads(thread_count(threads))
    {
      detail::Workspace w = workspace();
#pragma omp for schedule(dynamic, 16)
      for (long k = 0; k < blocks; ++k) {
        const std::size_t first = std::size_t(k) * detail::kLanes;
        fill_block(w.q, q, first, m, dof, rest.data());
        const std::size_t count = std::min<std::size_t>(detail::kLanes, m - first);
        const bool pairs = whole && undecided;
        for (std::size_t l = 0; l < std::size_t(detail::kLanes); ++l)
          w.pairs[l] = pairs && l < count ? &undecided[rest[first + l]] : nullptr;
        const detail::Block b = run(w, (1u << count) - 1, Mode::bounds, pairs, nullptr, from, to);
        for (std::size_t l = 0; l < count; ++l) {
          const std::size_t i = rest[first + l];
          out[i] = verdict_of(b, int(l));  // a probe's: colliding, or open
          open[i] = !whole && out[i] != Verdict::colliding;
          if (pairs && out[i] != Verdict::undecided) undecided[i].clear();
        }
      }
    }
    std::size_t kept = 0;
    for (std::size_t i : rest)
      if (open[i]) rest[kept++] = i;
    rest.resize(kept);
  }
  return true;
}

// Blocks of kLanes configurations, run in parallel; with `undecided`, each configuration's
// undecided pairs. The bounds mode by probed_bounds when the checker has a probe.
void RobotChecker::Impl::batch(const double* q, std::size_t n, Mode mode, Verdict* out,
                               std::vector<UndecidedPair>* undecided, int threads) const {
  check_threads(threads);
  if (n == 0) return;
  const std::size_t dof = layout.dof;
  for (std::size_t i = 0; i < n; ++i) validate(q + i * dof, i);
  if (mode == Mode::bounds && probed_bounds(q, n, out, undecided, threads)) return;
  // Batches gather the set tests that the links' and self pairs' bounding tests leave, each
  // block's run up front; a learnt order with a head (tests that each find a quarter of the
  // samples colliding) decides most lanes before most bounding tests, block by block.
  if (mode == Mode::spheres && batch_kernel && kernel_robot.head == 0 &&
      n > std::size_t(detail::kLanes)) {
    spheres_batches(q, n, out, threads);
    return;
  }
  const auto blocks = static_cast<long>((n + detail::kLanes - 1) / detail::kLanes);
  const int chunk = undecided ? 4 : 16;
#pragma omp parallel num_threads(thread_count(threads))
  {
    detail::Workspace w = workspace();
#pragma omp for schedule(dynamic, chunk)
    for (long k = 0; k < blocks; ++k) {
      const std::size_t first = std::size_t(k) * detail::kLanes;
      fill_block(w.q, q, first, n, dof);
      const std::size_t count = std::min<std::size_t>(detail::kLanes, n - first);
      if (undecided)
        for (std::size_t l = 0; l < std::size_t(detail::kLanes); ++l) {
          w.pairs[l] = l < count ? &undecided[first + l] : nullptr;
          if (l < count) undecided[first + l].clear();
        }
      const detail::Block b = run(w, (1u << count) - 1, mode, undecided != nullptr);
      for (std::size_t l = 0; l < count; ++l) {
        out[first + l] = verdict_of(b, int(l));
        if (undecided && out[first + l] != Verdict::undecided) undecided[first + l].clear();
      }
    }
  }
}

// Batches of kBatch blocks run in parallel, each by the batch kernel (its verdicts those of
// its blocks run one by one).
void RobotChecker::Impl::spheres_batches(const double* q, std::size_t n, Verdict* out,
                                         int threads) const {
  constexpr std::size_t kBatch = 32, kLanes = detail::kLanes;
  const std::size_t dof = layout.dof, tests = layout.links.size() + layout.pair_a.size();
  const std::size_t blocks = (n + kLanes - 1) / kLanes;
  const auto batches = static_cast<long>((blocks + kBatch - 1) / kBatch);
#pragma omp parallel num_threads(thread_count(threads))
  {
    detail::Workspace w = workspace();
    std::vector<std::vector<double>> qs(kBatch, w.q);
    std::vector<std::vector<float>> frames(kBatch, w.frames_f);
    std::vector<detail::Block> bs(kBatch);
    std::vector<float> gathered = w.frames_f;
    std::vector<unsigned char> need(kBatch * tests);
    std::vector<unsigned> unsure(kBatch);
#pragma omp for schedule(dynamic, 1)
    for (long k = 0; k < batches; ++k) {
      const std::size_t first_block = std::size_t(k) * kBatch;
      const std::size_t count = std::min(kBatch, blocks - first_block);
      for (std::size_t j = 0; j < count; ++j) {
        const std::size_t first = (first_block + j) * kLanes;
        fill_block(qs[j], q, first, n, dof);
        const std::size_t real = std::min(kLanes, n - first);
        bs[j] = block(w, qs[j], (1u << real) - 1, Mode::spheres, nullptr, 0, 0);
        bs[j].frames_f = frames[j].data();
      }
      detail::Batch t;
      t.blocks = bs.data();
      t.count = static_cast<int>(count);
      t.frames_f = gathered.data();
      t.need = need.data();
      t.unsure = unsure.data();
      batch_kernel(kernel_robot, *grid, t);
      for (std::size_t j = 0; j < count; ++j)
        for (std::size_t l = 0; l < kLanes && (first_block + j) * kLanes + l < n; ++l)
          out[(first_block + j) * kLanes + l] = verdict_of(bs[j], int(l));
    }
  }
}

void RobotChecker::validate(const double* q, std::size_t n) const {
  for (std::size_t i = 0; i < n; ++i) impl_->validate(q + i * impl_->layout.dof, i);
}

void RobotChecker::check(const double* q, std::size_t n, Mode mode, Verdict* out,
                         int threads) const {
  impl_->batch(q, n, mode, out, nullptr, threads);
}

Verdict RobotChecker::check(const double* q, Mode mode,
                            std::vector<UndecidedPair>* undecided) const {
  const Impl& m = *impl_;
  m.validate(q, 0);
  detail::Workspace& w = m.thread_workspace();
  fill_block(w.q, q, 0, 1, m.layout.dof);
  std::vector<UndecidedPair> pairs;
  w.pairs[0] = &pairs;
  const detail::Block b = m.run(w, 1u, mode, undecided != nullptr && mode == Mode::bounds);
  w.pairs[0] = nullptr;
  const Verdict v = verdict_of(b, 0);
  if (undecided && v == Verdict::undecided)
    undecided->insert(undecided->end(), pairs.begin(), pairs.end());
  return v;
}

bool RobotChecker::any_colliding(const double* q, std::size_t n) const {
  const Impl& m = *impl_;
  validate(q, n);
  detail::Workspace& w = m.thread_workspace();
  for (std::size_t first = 0; first < n; first += detail::kLanes) {
    fill_block(w.q, q, first, n, m.layout.dof);
    const std::size_t count = std::min<std::size_t>(detail::kLanes, n - first);
    const unsigned lanes = (1u << count) - 1u;
    if (m.run_any(w, lanes, Mode::spheres).colliding & lanes) return true;
  }
  return false;
}

void RobotChecker::check_bounds(const double* q, std::size_t n, Verdict* out,
                                std::vector<UndecidedPair>* undecided, int threads) const {
  impl_->batch(q, n, Mode::bounds, out, undecided, threads);
}

std::size_t RobotChecker::edge_steps(const double* q0, const double* q1, double resolution) const {
  return steps_of(q0, q1, impl_->layout.dof, resolution, 0);
}

void RobotChecker::validate_edges(const double* q0, const double* q1, std::size_t n,
                                  double resolution) const {
  const std::size_t dof = impl_->layout.dof;
  check_resolution(resolution);
  for (std::size_t i = 0; i < n; ++i) {
    impl_->validate(q0 + i * dof, i);
    impl_->validate(q1 + i * dof, i);
    steps_of(q0 + i * dof, q1 + i * dof, dof, resolution, i);
  }
}

Verdict RobotChecker::check_edge(const double* q0, const double* q1, double resolution, Mode mode,
                                 std::vector<double>* undecided_t, std::size_t* checked) const {
  const Impl& m = *impl_;
  m.validate(q0, 0);
  m.validate(q1, 1);
  edge_steps(q0, q1, resolution);  // validates the resolution
  detail::Workspace& w = m.thread_workspace();
  std::size_t count = 0;
  const Verdict v = m.edge(w, q0, q1, resolution, mode, undecided_t, count);
  if (checked) *checked = count;
  return v;
}

std::size_t RobotChecker::check_edges(const double* q0, const double* q1, std::size_t n,
                                      double resolution, Mode mode, Verdict* out,
                                      int threads) const {
  const Impl& m = *impl_;
  const std::size_t dof = m.layout.dof;
  check_threads(threads);
  validate_edges(q0, q1, n, resolution);
  std::size_t total = 0;
#pragma omp parallel num_threads(thread_count(threads)) reduction(+ : total)
  {
    detail::Workspace w = m.workspace();
#pragma omp for schedule(dynamic, 4)
    for (long i = 0; i < static_cast<long>(n); ++i) {
      std::size_t count = 0;
      out[i] = m.edge(w, q0 + std::size_t(i) * dof, q1 + std::size_t(i) * dof, resolution, mode,
                      nullptr, count);
      total += count;
    }
  }
  return total;
}

}  // namespace medspheres::check
