#include "pair_table.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "medspheres/scalar_distance.h"

namespace medspheres::check::detail {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// The spectral norm of a symmetric matrix.
double norm(const Matrix3d& m) {
  return Eigen::SelfAdjointEigenSolver<Matrix3d>(m, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .cwiseAbs()
      .maxCoeff();
}

double length(const double* v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

// Bounds of a step's rotation R (revolute: R(t) = P + cos t C + sin t S, every t): rho >=
// |R x| / |x|, and (revolute) kappa >= |dR/dt x| / |x|. R^T R expands into a constant and
// terms in cos t, sin t, cos 2t, sin 2t, so its norm is at most the sum of theirs; likewise
// dR/dt^T dR/dt = (C^T C + S^T S) / 2 + cos 2t (S^T S - C^T C) / 2 - sin 2t (C^T S + S^T C)
// / 2. Both are 1 (and a hair) for a rotation about a unit axis; 1e-9 relative more for
// the rounding of these sums.
void rotation_bounds(const FrameStep& s, double& rho, double& kappa) {
  const Matrix3d P = step_matrix(s.P), C = step_matrix(s.C), S = step_matrix(s.S);
  if (s.prismatic) {
    rho = std::sqrt(norm(P.transpose() * P)) * (1.0 + 1e-9);
    kappa = 0.0;
    return;
  }
  const Matrix3d CC = C.transpose() * C, SS = S.transpose() * S, CS = C.transpose() * S;
  const double r2 = norm(P.transpose() * P + (CC + SS) / 2) + norm((CC - SS) / 2) +
                    norm((CS + CS.transpose()) / 2) + norm(P.transpose() * C + C.transpose() * P) +
                    norm(P.transpose() * S + S.transpose() * P);
  const double k2 = norm((CC + SS) / 2) + norm((SS - CC) / 2) + norm((CS + CS.transpose()) / 2);
  rho = std::sqrt(r2) * (1.0 + 1e-9);
  kappa = std::sqrt(k2) * (1.0 + 1e-9);
}

// One side of a pair: the steps from the common ancestor frame down to the link's frame
// (top first), and its spheres.
struct Side {
  std::vector<int> steps;
  std::vector<Vector3d> centre;
  std::vector<double> radius;
};

// X_PF of step s at position q (of its source).
void step_pose(const FrameStep& s, double q, Matrix3d& R, Vector3d& p) {
  const double t = q * s.multiplier + s.offset;
  p = Vector3d(s.u[0], s.u[1], s.u[2]);
  if (s.prismatic) {
    R = step_matrix(s.P);
    p += t * Vector3d(s.v[0], s.v[1], s.v[2]);
    return;
  }
  R = step_matrix(s.P) + std::cos(t) * step_matrix(s.C) + std::sin(t) * step_matrix(s.S);
}

// The frames from f up to W (f first), by the steps that pose them.
std::vector<int> ancestors(const std::vector<int>& step_of, const RobotLayout& layout, int f) {
  std::vector<int> out{f};
  while (f != 0) {
    f = layout.steps[static_cast<std::size_t>(step_of[static_cast<std::size_t>(f)])].parent;
    out.push_back(f);
  }
  return out;
}

struct PairBake {
  explicit PairBake(const RobotLayout& l) : layout(l) {}
  const RobotLayout& layout;
  Side side[2];
  int sources = 0;
  int source[3] = {0, 0, 0};
  double lower[3] = {0, 0, 0}, upper[3] = {0, 0, 0};
  double weight[3] = {0, 0, 0};  // m per unit of each position
  int n[3] = {1, 1, 1};
  std::vector<Vector3d> posed[2];  // gap()'s workspace

  int slot(int source_index) const {
    for (int j = 0; j < sources; ++j)
      if (source[j] == source_index) return j;
    return -1;
  }

  // The sets' least gap at positions q (per slot), posed in the common ancestor frame.
  double gap(const double* q) {
    for (int k = 0; k < 2; ++k) {
      Matrix3d R = Matrix3d::Identity();
      Vector3d p = Vector3d::Zero();
      for (int i : side[k].steps) {
        const FrameStep& s = layout.steps[static_cast<std::size_t>(i)];
        Matrix3d r;
        Vector3d u;
        step_pose(s, q[slot(s.source)], r, u);
        p = R * u + p;
        R = R * r;
      }
      posed[k].resize(side[k].centre.size());
      for (std::size_t i = 0; i < side[k].centre.size(); ++i)
        posed[k][i] = medspheres::detail::affine(R, side[k].centre[i], p);
    }
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < posed[0].size(); ++i)
      for (std::size_t j = 0; j < posed[1].size(); ++j)
        best = std::min(best, medspheres::detail::distance(posed[0][i], posed[1][j]) -
                                  side[0].radius[i] - side[1].radius[j]);
    return best;
  }

  // Sets weight[]: per position, how fast it moves a centre of either side at most.
  void weigh() {
    for (int k = 0; k < 2; ++k) {
      const Side& sd = side[k];
      double m = 0.0;  // the farthest centre from the current frame's origin
      for (const Vector3d& c : sd.centre) m = std::max(m, c.norm());
      std::vector<double> local(sd.steps.size()), rho(sd.steps.size());
      for (std::size_t i = sd.steps.size(); i-- > 0;) {
        const FrameStep& s = layout.steps[static_cast<std::size_t>(sd.steps[i])];
        double kappa = 0.0;
        rotation_bounds(s, rho[i], kappa);
        const int j = slot(s.source);
        const double travel = std::max(std::abs(lower[j] * s.multiplier + s.offset),
                                       std::abs(upper[j] * s.multiplier + s.offset));
        local[i] = std::abs(s.multiplier) * (s.prismatic ? length(s.v) : kappa * m);
        m = rho[i] * m + length(s.u) + (s.prismatic ? length(s.v) * travel : 0.0);
      }
      double above = 1.0;  // the rotations above step i on the path
      for (std::size_t i = 0; i < sd.steps.size(); ++i) {
        const FrameStep& s = layout.steps[static_cast<std::size_t>(sd.steps[i])];
        weight[slot(s.source)] += local[i] * above * (1.0 + 1e-9);
        above *= rho[i];
      }
    }
  }

  // Cells per position: doubled where a cell moves the sets most, up to max_cells.
  void size(std::size_t max_cells) {
    std::size_t total = 1;
    for (;;) {
      int best = -1;
      double most = 0.0;
      for (int j = 0; j < sources; ++j) {
        const double move = weight[j] * (upper[j] - lower[j]) / n[j];
        if (move > most && n[j] < static_cast<int>(kFineCells)) best = j, most = move;
      }
      if (best < 0 || total * 2 > max_cells) return;
      n[best] *= 2;
      total *= 2;
    }
  }

  // Sets the sides' steps (from the common ancestor frame down to each link's frame), their
  // spheres and the positions of links a and o; false when the pair has no table (more
  // than three positions, one without finite limits, a side without spheres).
  bool paths(const RobotModel& model, const std::vector<int>& step_of, int a, int o) {
    const int link[2] = {a, o};
    std::vector<int> up[2];
    for (int s = 0; s < 2; ++s)
      up[s] = ancestors(step_of, layout, layout.links[static_cast<std::size_t>(link[s])].frame);
    // Drop the common ancestors (the frames both chains end in).
    while (up[0].size() > 1 && up[1].size() > 1 &&
           up[0][up[0].size() - 2] == up[1][up[1].size() - 2])
      up[0].pop_back(), up[1].pop_back();
    for (int s = 0; s < 2; ++s) {
      const LinkLayout& l = layout.links[static_cast<std::size_t>(link[s])];
      for (std::size_t i = up[s].size() - 1; i-- > 0;) {  // top first, the ancestor excluded
        const int step = step_of[static_cast<std::size_t>(up[s][i])];
        side[s].steps.push_back(step);
        const int q = layout.steps[static_cast<std::size_t>(step)].source;
        if (slot(q) >= 0) continue;
        const Joint* j = model.find_joint(layout.joint_names[static_cast<std::size_t>(q)]);
        if (sources == 3 || j == nullptr || !j->limits || j->type == JointType::kContinuous ||
            !(j->limits->upper > j->limits->lower) ||
            !std::isfinite(j->limits->upper - j->limits->lower))
          return false;
        source[sources] = q;
        lower[sources] = j->limits->lower;
        upper[sources] = j->limits->upper;
        ++sources;
      }
      for (std::uint32_t i = l.begin[l.spheres]; i < l.begin[l.spheres] + l.count[l.spheres]; ++i) {
        side[s].centre.emplace_back(layout.x[i], layout.y[i], layout.z[i]);
        side[s].radius.push_back(layout.r[i]);
      }
      if (side[s].centre.empty()) return false;
    }
    return true;
  }

  // Marks the free cells of the box [lo, hi) (cells per position; h: a cell's width in
  // each position) in bits, splitting the box where it moves the sets most; returns how
  // many. Free: the gap at the box's centre less the box's motion bound beyond `limit`.
  std::size_t mark(const int* lo, const int* hi, const double* h, double limit,
                   const std::uint32_t* stride, std::vector<std::uint64_t>& bits) {
    double q[3] = {0, 0, 0}, move = 0.0, widest = 0.0;
    int split = -1;
    for (int j = 0; j < sources; ++j) {
      q[j] = lower[j] + 0.5 * (lo[j] + hi[j]) * h[j];
      const double half = 0.5 * (hi[j] - lo[j]) * h[j] * (1.0 + 1e-6);
      move += weight[j] * half;
      if (hi[j] - lo[j] > 1 && weight[j] * half > widest) split = j, widest = weight[j] * half;
    }
    move *= 1.0 + 1e-9;
    const double d = gap(q);
    if (d - move > limit) {
      std::size_t free = 0;
      for (int z = lo[2]; z < (sources > 2 ? hi[2] : 1); ++z)
        for (int y = lo[1]; y < (sources > 1 ? hi[1] : 1); ++y)
          for (int x = lo[0]; x < (sources > 0 ? hi[0] : 1); ++x, ++free) {
            const std::uint32_t c = static_cast<std::uint32_t>(x) * stride[0] +
                                    static_cast<std::uint32_t>(y) * stride[1] +
                                    static_cast<std::uint32_t>(z) * stride[2];
            bits[c >> 6] |= std::uint64_t(1) << (c & 63);
          }
      return free;
    }
    if (d + move <= limit || split < 0) return 0;  // no cell of the box is free
    int mid_hi[3] = {hi[0], hi[1], hi[2]}, mid_lo[3] = {lo[0], lo[1], lo[2]};
    mid_hi[split] = mid_lo[split] = (lo[split] + hi[split]) / 2;
    return mark(lo, mid_hi, h, limit, stride, bits) + mark(mid_lo, hi, h, limit, stride, bits);
  }
};

}  // namespace

PairTables::PairTables(const RobotModel& model, const RobotLayout& layout, double threshold,
                       std::size_t max_cells) {
  views_.resize(layout.pair_a.size());
  if (max_cells == 0) return;
  std::vector<int> step_of(static_cast<std::size_t>(layout.frames), -1);
  for (std::size_t i = 0; i < layout.steps.size(); ++i)
    step_of[static_cast<std::size_t>(layout.steps[i].frame)] = static_cast<int>(i);
  const double pad = 1e-9 * (1.0 + layout.extent);
  double free_sum = 0.0;
  for (std::size_t k = 0; k < layout.pair_a.size(); ++k) {
    PairBake b(layout);
    bool ok = b.paths(model, step_of, static_cast<int>(layout.pair_a[k]),
                      static_cast<int>(layout.pair_b[k]));
    // Every position a slot, at most kMaxTableSlots of them.
    int slot[3] = {0, 0, 0};
    for (int j = 0; j < b.sources && ok; ++j) {
      slot[j] = -1;
      for (std::size_t i = 0; i < slots_.size(); ++i)
        if (slots_[i].source == b.source[j]) slot[j] = static_cast<int>(i);
      if (slot[j] < 0 && slots_.size() + 1 > std::size_t(kMaxTableSlots)) ok = false;
    }
    if (!ok) continue;
    for (int j = 0; j < b.sources; ++j)
      if (slot[j] < 0) {
        slot[j] = static_cast<int>(slots_.size());
        slots_.push_back({b.source[j], b.lower[j], kFineCells / (b.upper[j] - b.lower[j])});
      }
    b.weigh();
    b.size(max_cells);
    PairTableView& v = views_[k];
    v.sources = b.sources;
    std::uint32_t stride = 1;
    double h[3] = {0, 0, 0};
    for (int j = 0; j < b.sources; ++j) {
      v.slot[j] = slot[j];
      v.shift[j] = 16 - static_cast<int>(std::lround(std::log2(b.n[j])));
      h[j] = (b.upper[j] - b.lower[j]) / b.n[j];
      v.stride[j] = stride;
      stride *= static_cast<std::uint32_t>(b.n[j]);
    }
    std::vector<std::uint64_t> bits((stride + 63) / 64, 0);
    const int lo[3] = {0, 0, 0}, hi[3] = {b.n[0], b.n[1], b.n[2]};
    const std::size_t free = b.mark(lo, hi, h, threshold + pad, v.stride, bits);
    if (free == 0) {
      views_[k] = PairTableView{};
      continue;
    }
    bits_.push_back(std::move(bits));
    v.bits = bits_.back().data();
    v.all_free = free == stride;
    ++tables_;
    free_sum += double(free) / stride;
  }
  free_share_ = tables_ ? free_sum / double(tables_) : 0.0;
}

}  // namespace medspheres::check::detail
