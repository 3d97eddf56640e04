// Traversals of SphereTree: tree and tree, tree and point, tree and ProximityTarget.
// Everything is computed in the first tree's frame A and converted to W at the end.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "medspheres/sphere_tree.h"
#include "proximity_bounds.h"
#include "sphere_tree_layout.h"

namespace medspheres {
namespace {

using detail::BallNode;
using detail::PackedSphere;
using detail::RssNode;
using detail::RssView;
using Layout = SphereTree::Layout;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();

inline Eigen::Vector3d load(const double* v) {
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

void check_pose(const Eigen::Isometry3d& X, const char* name) {
  if (!X.matrix().allFinite())
    throw std::invalid_argument(std::string(name) + " has a non-finite entry");
}

void check_options(const DistanceOptions& o) {
  if (!(o.abs_err >= 0.0) || !std::isfinite(o.abs_err))
    throw std::invalid_argument("DistanceOptions::abs_err must be finite and >= 0");
  if (!(o.rel_err >= 0.0) || !std::isfinite(o.rel_err))
    throw std::invalid_argument("DistanceOptions::rel_err must be finite and >= 0");
  if (std::isnan(o.upper_bound)) throw std::invalid_argument("DistanceOptions::upper_bound is NaN");
}

// The pose of frame B in frame A, and W's x axis expressed in A (the normal used when
// two centres coincide).
struct Frame {
  Eigen::Matrix3d R;    // R_AB
  Eigen::Vector3d p;    // p_AoBo_A
  Eigen::Vector3d x_W;  // x axis of W, expressed in A

  Frame(const Eigen::Isometry3d& X_WA, const Eigen::Isometry3d& X_WB) {
    const Eigen::Matrix3d R_AW = X_WA.linear().transpose();
    R = R_AW * X_WB.linear();
    p = R_AW * (X_WB.translation() - X_WA.translation());
    x_W = R_AW.col(0);
  }
};

// --- node access, uniform over the two node kinds ---------------------------------------

inline bool is_leaf(const RssNode& n) {
  return n.count > 0;
}
inline bool is_leaf(const BallNode& n) {
  return n.count > 0;
}
inline double bound_radius(const RssNode& n) {
  return n.ball_r;
}
inline double bound_radius(const BallNode& n) {
  return n.r;
}

// The node's RSS in centre form, in A: \p c is the node's reference centre (its ball's)
// already moved to A, R rotates the node's frame into A.
inline RssView rss_view(const RssNode& n, const Eigen::Matrix3d& R, const Eigen::Vector3d& c) {
  RssView v;
  v.c = c + R * load(n.o);
  v.u = R * load(n.u);
  v.v = R * load(n.v);
  v.h0 = n.half[0];
  v.h1 = n.half[1];
  v.r = n.r;
  return v;
}

inline RssView rss_view(const BallNode& n, const Eigen::Matrix3d&, const Eigen::Vector3d& c) {
  RssView v;
  v.c = c;
  v.r = n.r;
  return v;
}

// Lower bound on the signed distance of any sphere below a and any sphere below b, with
// the nodes' ball centres already in A, or infinity when the bounding balls alone show
// that the bound exceeds prune_at: first the two balls' gap, then, for RSS nodes,
// the gap of the RSS along the line through the ball centres (see proximity_bounds.h;
// an RSS's extent about the ball centre adds the rectangle's offset o), and for signed
// queries minus the two largest radii.
template <class NA, class NB>
double node_pair_bound(const NA& a, const Eigen::Vector3d& ca, const NB& b,
                       const Eigen::Vector3d& cb, const Eigen::Matrix3d& R_AB, double prune_at,
                       bool is_signed) {
  const Eigen::Vector3d w = cb - ca;
  // The balls alone prune most pairs: decide those without a square root.
  const double reach = prune_at + bound_radius(a) + bound_radius(b);
  const double len2 = w.squaredNorm();
  if (reach < 0.0 || len2 > reach * reach) return kInf;
  const double len = std::sqrt(len2);
  double lb = len - bound_radius(a) - bound_radius(b);
  if (lb >= prune_at) return lb;
  constexpr bool rss_a = std::is_same_v<NA, RssNode>;
  constexpr bool rss_b = std::is_same_v<NB, RssNode>;
  if constexpr (rss_a || rss_b) {
    if (len > 0.0) {
      const Eigen::Vector3d d = w / len;
      double gap = len;
      if constexpr (rss_a) {
        const Eigen::Vector3d u = load(a.u), v = load(a.v);
        gap -= d.dot(load(a.o)) + detail::rectangle_extent(a.half[0], a.half[1], u, v, d) + a.r;
      } else {
        gap -= a.r;
      }
      if constexpr (rss_b) {
        const Eigen::Vector3d d_B = R_AB.transpose() * d;
        const Eigen::Vector3d u = load(b.u), v = load(b.v);
        gap += d_B.dot(load(b.o)) - detail::rectangle_extent(b.half[0], b.half[1], u, v, d_B) - b.r;
      } else {
        gap -= b.r;
      }
      lb = std::max(lb, gap);
    }
  }
  if (is_signed) lb = std::max(lb, -(a.max_r + b.max_r));
  return lb;
}

template <class N>
const N* nodes_of(const Layout& l) {
  if constexpr (std::is_same_v<N, RssNode>)
    return l.rss_nodes;
  else
    return l.ball_nodes;
}

// Extent of a tree's geometry about the origin of its frame: the root's bounding ball.
template <class N>
double tree_extent(const Layout& l) {
  const N& root = nodes_of<N>(l)[0];
  return load(root.c).norm() + bound_radius(root);
}

// --- the pair of balls: signed distance, normal, witness points --------------------------

struct PairValue {
  double sd;
  Eigen::Vector3d n;   // from a towards b, in A
  Eigen::Vector3d pa;  // witness on a, in A
  Eigen::Vector3d pb;  // witness on b, in A
};

inline PairValue ball_pair(const Eigen::Vector3d& ca, double ra, const Eigen::Vector3d& cb,
                           double rb, const Eigen::Vector3d& fallback_normal) {
  PairValue v;
  const Eigen::Vector3d diff = cb - ca;
  const double len = diff.norm();
  v.sd = len - (ra + rb);
  v.n = len > 0.0 ? Eigen::Vector3d(diff / len) : fallback_normal;
  v.pa = ca + v.n * ra;
  v.pb = cb - v.n * rb;
  return v;
}

// Pruning rule of FCL's distance traversals: a lower bound c is pruned when
// c >= best - abs_err and c (1 + rel_err) >= best.
struct Threshold {
  double abs_err;
  double rel_err;
  double operator()(double best) const { return std::max(best - abs_err, best / (1.0 + rel_err)); }
};

struct Best {
  double value;
  std::int32_t a = -1;   // tree position of the sphere of A
  std::intptr_t b = -1;  // tree position of the sphere of B, or the primitive id
  Eigen::Vector3d pa = Eigen::Vector3d::Zero();
  Eigen::Vector3d pb = Eigen::Vector3d::Zero();
};

TreeDistance finish(const Best& best, const Layout& la, const Layout* lb,
                    const Eigen::Isometry3d& X_WA, const QueryStats& stats) {
  TreeDistance out;
  out.distance = best.value;
  out.stats = stats;
  if (best.a >= 0) {
    out.sphere_a = la.original_index[best.a];
    out.primitive_b = lb != nullptr ? lb->original_index[best.b] : best.b;
    out.p_WPa = X_WA * best.pa;
    out.p_WPb = X_WA * best.pb;
  }
  return out;
}

// --- tree and tree ---------------------------------------------------------------------

template <class NA, class NB>
class PairTraversal {
 public:
  PairTraversal(const Layout& la, const Layout& lb, const Frame& frame)
      : na_(nodes_of<NA>(la)),
        nb_(nodes_of<NB>(lb)),
        sa_(la.spheres),
        sb_(lb.spheres),
        frame_(frame) {}

  // Distance: the smallest signed distance of a pair below upper_bound; with
  // stop_at_overlap, the first pair with signed distance <= 0 ends the search.
  Best distance(const DistanceOptions& options, bool stop_at_overlap, QueryStats& stats) {
    stats_ = &stats;
    is_signed_ = !stop_at_overlap;
    stop_at_overlap_ = stop_at_overlap;
    threshold_ = Threshold{options.abs_err, options.rel_err};
    best_.value = options.upper_bound;
    prune_at_ = threshold_(best_.value);
    const Pair root = root_pair(prune_at_);
    if (root.lb < prune_at_) distance_recurse(root);
    return best_;
  }

  // Collision: up to max_contacts (>= 1) overlapping pairs, in traversal order.
  void collide(std::size_t max_contacts, std::vector<TreeContact>* out, double slack,
               const Eigen::Isometry3d& X_WA, QueryStats& stats, std::size_t& found) {
    stats_ = &stats;
    is_signed_ = false;
    max_contacts_ = max_contacts;
    out_ = out;
    X_WA_ = &X_WA;
    slack_ = slack;
    found_ = 0;
    const Pair root = root_pair(slack);
    if (root.lb <= slack) collide_recurse(root);
    found = found_;
  }

 private:
  Eigen::Vector3d center_a(std::int32_t i) const { return load(na_[i].c); }
  Eigen::Vector3d center_b(std::int32_t j) const { return frame_.R * load(nb_[j].c) + frame_.p; }

  // A node pair with the nodes' centres in A, and its lower bound.
  struct Pair {
    std::int32_t i, j;
    Eigen::Vector3d ca, cb;
    double lb;
  };

  Pair root_pair(double prune_at) {
    Pair p{0, 0, center_a(0), center_b(0), 0.0};
    p.lb = bound(p, prune_at);
    return p;
  }

  double bound(const Pair& p, double prune_at) {
    ++stats_->bv_tests;
    return node_pair_bound(na_[p.i], p.ca, nb_[p.j], p.cb, frame_.R, prune_at, is_signed_);
  }

  // The two child pairs of a pair (opening one node), nearest first.
  void expand(const Pair& p, double prune_at, Pair out[2]) {
    if (open_a(p.i, p.j)) {
      for (int k = 0; k < 2; ++k) {
        const std::int32_t c = na_[p.i].first + k;
        out[k] = Pair{c, p.j, center_a(c), p.cb, 0.0};
      }
    } else {
      for (int k = 0; k < 2; ++k) {
        const std::int32_t c = nb_[p.j].first + k;
        out[k] = Pair{p.i, c, p.ca, center_b(c), 0.0};
      }
    }
    out[0].lb = bound(out[0], prune_at);
    out[1].lb = bound(out[1], prune_at);
    if (out[1].lb < out[0].lb) std::swap(out[0], out[1]);
  }

  // Which node to open: the internal one, or the larger of two internal ones.
  bool open_a(std::int32_t i, std::int32_t j) const {
    if (is_leaf(na_[i])) return false;
    if (is_leaf(nb_[j])) return true;
    return bound_radius(na_[i]) >= bound_radius(nb_[j]);
  }

  void distance_leaves(std::int32_t i, std::int32_t j) {
    const NA& a = na_[i];
    const NB& b = nb_[j];
    const Eigen::Vector3d ca = load(a.c);
    for (std::int32_t kb = b.first; kb < b.first + b.count; ++kb) {
      const PackedSphere& sb = sb_[kb];
      const Eigen::Vector3d cb = frame_.R * load(sb.c) + frame_.p;
      // Skip the whole leaf of A when this sphere is too far from A's bounding ball.
      const double reach_a = best_.value + sb.r + bound_radius(a);
      if (reach_a <= 0.0 || (cb - ca).squaredNorm() > reach_a * reach_a) continue;
      for (std::int32_t ka = a.first; ka < a.first + a.count; ++ka) {
        const PackedSphere& sa = sa_[ka];
        ++stats_->leaf_tests;
        // A pair that cannot beat the best is rejected on its squared length.
        const double reach = best_.value + (sa.r + sb.r);
        const double len2 = (cb - load(sa.c)).squaredNorm();
        if (reach <= 0.0 || len2 > reach * reach) continue;
        const double sd = std::sqrt(len2) - (sa.r + sb.r);
        if (sd < best_.value) {
          const PairValue v = ball_pair(load(sa.c), sa.r, cb, sb.r, frame_.x_W);
          best_.value = v.sd;
          best_.a = ka;
          best_.b = kb;
          best_.pa = v.pa;
          best_.pb = v.pb;
          prune_at_ = threshold_(best_.value);
          if (stop_at_overlap_ && sd <= 0.0) {
            done_ = true;
            return;
          }
        }
      }
    }
  }

  void distance_recurse(const Pair& p) {
    if (is_leaf(na_[p.i]) && is_leaf(nb_[p.j])) {
      distance_leaves(p.i, p.j);
      return;
    }
    Pair next[2];
    expand(p, prune_at_, next);
    for (const Pair& q : next) {
      if (q.lb < prune_at_) distance_recurse(q);
      if (done_) return;
    }
  }

  void collide_leaves(std::int32_t i, std::int32_t j) {
    const NA& a = na_[i];
    const NB& b = nb_[j];
    for (std::int32_t kb = b.first; kb < b.first + b.count; ++kb) {
      const PackedSphere& sb = sb_[kb];
      const Eigen::Vector3d cb = frame_.R * load(sb.c) + frame_.p;
      for (std::int32_t ka = a.first; ka < a.first + a.count; ++ka) {
        const PackedSphere& sa = sa_[ka];
        ++stats_->leaf_tests;
        if ((cb - load(sa.c)).norm() > sa.r + sb.r) continue;
        if (out_ != nullptr) {
          const PairValue v = ball_pair(load(sa.c), sa.r, cb, sb.r, frame_.x_W);
          TreeContact c;
          c.p_WC = *X_WA_ * (0.5 * (v.pa + v.pb));
          c.n_W = X_WA_->linear() * v.n;
          c.depth = -v.sd;
          c.sphere_a = ka;
          c.primitive_b = kb;
          out_->push_back(c);
        }
        ++found_;
        if (found_ >= max_contacts_) {
          done_ = true;
          return;
        }
      }
    }
  }

  void collide_recurse(const Pair& p) {
    if (is_leaf(na_[p.i]) && is_leaf(nb_[p.j])) {
      collide_leaves(p.i, p.j);
      return;
    }
    Pair next[2];
    expand(p, slack_, next);
    for (const Pair& q : next) {
      if (q.lb <= slack_) collide_recurse(q);
      if (done_) return;
    }
  }

  const NA* na_;
  const NB* nb_;
  const PackedSphere* sa_;
  const PackedSphere* sb_;
  Frame frame_;
  QueryStats* stats_ = nullptr;
  bool is_signed_ = false;
  bool stop_at_overlap_ = false;
  bool done_ = false;
  Threshold threshold_{0.0, 0.0};
  double prune_at_ = kInf;
  Best best_{kInf};
  // collision
  std::size_t max_contacts_ = 1;
  std::size_t found_ = 0;
  std::vector<TreeContact>* out_ = nullptr;
  const Eigen::Isometry3d* X_WA_ = nullptr;
  double slack_ = 0.0;
};

// Rounding allowance of the collision traversals' node tests, so that touching pairs
// are never pruned: 64 ulps of the scene's extent.
double collision_slack(double extent_a, double extent_b, const Frame& frame) {
  return 64.0 * kEps * (extent_a + extent_b + frame.p.norm());
}

// Calls f(PairTraversal<NA, NB>&) with the node types of the two trees.
template <class F>
void with_pair_traversal(const Layout& la, const Layout& lb, const Frame& frame, F&& f) {
  const bool ra = la.kind == BoundingVolumeKind::rss;
  const bool rb = lb.kind == BoundingVolumeKind::rss;
  if (ra && rb) {
    PairTraversal<RssNode, RssNode> t(la, lb, frame);
    f(t, tree_extent<RssNode>(la), tree_extent<RssNode>(lb));
  } else if (ra) {
    PairTraversal<RssNode, BallNode> t(la, lb, frame);
    f(t, tree_extent<RssNode>(la), tree_extent<BallNode>(lb));
  } else if (rb) {
    PairTraversal<BallNode, RssNode> t(la, lb, frame);
    f(t, tree_extent<BallNode>(la), tree_extent<RssNode>(lb));
  } else {
    PairTraversal<BallNode, BallNode> t(la, lb, frame);
    f(t, tree_extent<BallNode>(la), tree_extent<BallNode>(lb));
  }
}

TreeDistance tree_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                           const Eigen::Isometry3d& X_WB, const DistanceOptions& options,
                           bool stop_at_overlap) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  check_options(options);
  const Layout* la = tree_layout(a);
  const Layout* lb = tree_layout(b);
  TreeDistance out;
  out.distance = options.upper_bound;
  if (la == nullptr || lb == nullptr || la->num_nodes == 0 || lb->num_nodes == 0) return out;
  const Frame frame(X_WA, X_WB);
  QueryStats stats;
  Best best{options.upper_bound};
  with_pair_traversal(*la, *lb, frame, [&](auto& t, double, double) {
    best = t.distance(options, stop_at_overlap, stats);
  });
  return finish(best, *la, lb, X_WA, stats);
}

std::size_t tree_contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                          const Eigen::Isometry3d& X_WB, std::size_t max_contacts,
                          std::vector<TreeContact>* out, QueryStats* stats) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  const Layout* la = tree_layout(a);
  const Layout* lb = tree_layout(b);
  QueryStats local;
  std::size_t found = 0;
  if (max_contacts > 0 && la != nullptr && lb != nullptr && la->num_nodes > 0 &&
      lb->num_nodes > 0) {
    const Frame frame(X_WA, X_WB);
    const std::size_t before = out != nullptr ? out->size() : 0;
    with_pair_traversal(*la, *lb, frame, [&](auto& t, double extent_a, double extent_b) {
      t.collide(max_contacts, out, collision_slack(extent_a, extent_b, frame), X_WA, local, found);
    });
    if (out != nullptr) {
      for (std::size_t k = before; k < out->size(); ++k) {
        TreeContact& c = (*out)[k];
        c.sphere_a = la->original_index[c.sphere_a];
        c.primitive_b = lb->original_index[c.primitive_b];
      }
    }
  }
  if (stats != nullptr) *stats = local;
  return found;
}

// --- tree and point --------------------------------------------------------------------

template <class N>
class PointTraversal {
 public:
  PointTraversal(const Layout& l, const Eigen::Vector3d& q, const Eigen::Vector3d& x_W)
      : nodes_(nodes_of<N>(l)), spheres_(l.spheres), q_(q), x_W_(x_W) {}

  Best run(const DistanceOptions& options, QueryStats& stats) {
    stats_ = &stats;
    threshold_ = Threshold{options.abs_err, options.rel_err};
    best_.value = options.upper_bound;
    prune_at_ = threshold_(best_.value);
    if (bound(0) < prune_at_) recurse(0);
    return best_;
  }

 private:
  double bound(std::int32_t i) {
    ++stats_->bv_tests;
    const N& n = nodes_[i];
    const Eigen::Vector3d c = load(n.c);
    double lb = std::max((q_ - c).norm() - bound_radius(n), -n.max_r);
    if (lb < prune_at_) {
      RssView point;
      point.c = q_;
      lb = std::max(lb, detail::rss_gap(rss_view(n, Eigen::Matrix3d::Identity(), c), point, -kInf));
    }
    return lb;
  }

  void recurse(std::int32_t i) {
    const N& n = nodes_[i];
    if (is_leaf(n)) {
      for (std::int32_t k = n.first; k < n.first + n.count; ++k) {
        const PackedSphere& s = spheres_[k];
        ++stats_->leaf_tests;
        const PairValue v = ball_pair(load(s.c), s.r, q_, 0.0, x_W_);
        if (v.sd < best_.value) {
          best_.value = v.sd;
          best_.a = k;
          best_.pa = v.pa;
          best_.pb = q_;
          prune_at_ = threshold_(best_.value);
        }
      }
      return;
    }
    std::int32_t c[2] = {n.first, n.first + 1};
    double lb[2] = {bound(c[0]), bound(c[1])};
    const int first = lb[1] < lb[0] ? 1 : 0;
    for (int k : {first, 1 - first})
      if (lb[k] < prune_at_) recurse(c[k]);
  }

  const N* nodes_;
  const PackedSphere* spheres_;
  Eigen::Vector3d q_;
  Eigen::Vector3d x_W_;
  QueryStats* stats_ = nullptr;
  Threshold threshold_{0.0, 0.0};
  double prune_at_ = kInf;
  Best best_{kInf};
};

// --- tree and target -------------------------------------------------------------------

// A target node's bounds in centre form, expressed in A.
RssView target_view(const Rss& bounds, const Frame& frame) {
  RssView v;
  const double h0 = 0.5 * bounds.length[0], h1 = 0.5 * bounds.length[1];
  v.c = frame.R * bounds.center() + frame.p;
  v.u = frame.R * bounds.axis.col(0);
  v.v = frame.R * bounds.axis.col(1);
  v.h0 = h0;
  v.h1 = h1;
  v.r = bounds.radius;
  return v;
}

double view_bound_radius(const RssView& v) {
  return std::sqrt(v.h0 * v.h0 + v.h1 * v.h1) + v.r;
}

template <class N>
class TargetTraversal {
 public:
  TargetTraversal(const Layout& la, const ProximityTarget& target, const Frame& frame)
      : na_(nodes_of<N>(la)), sa_(la.spheres), target_(target), frame_(frame) {
    R_BA_ = frame.R.transpose();
    p_BA_ = -(R_BA_ * frame.p);
  }

  Best distance(const TargetNode& root, const DistanceOptions& options, bool stop_at_overlap,
                QueryStats& stats) {
    stats_ = &stats;
    is_signed_ = !stop_at_overlap;
    stop_at_overlap_ = stop_at_overlap;
    threshold_ = Threshold{options.abs_err, options.rel_err};
    best_.value = options.upper_bound;
    prune_at_ = threshold_(best_.value);
    const Item item = make_item(root);
    if (bound(0, item, prune_at_) < prune_at_) distance_recurse(0, item);
    return best_;
  }

  void collide(const TargetNode& root, std::size_t max_contacts, std::vector<TreeContact>* out,
               double slack, const Eigen::Isometry3d& X_WA, QueryStats& stats, std::size_t& found) {
    stats_ = &stats;
    max_contacts_ = max_contacts;
    out_ = out;
    X_WA_ = &X_WA;
    slack_ = slack;
    found_ = 0;
    const Item item = make_item(root);
    if (bound(0, item, slack) <= slack) collide_recurse(0, item);
    found = found_;
  }

 private:
  // A target node with its bounds already in A.
  struct Item {
    TargetNode node;
    RssView view;
    double bound_r = 0.0;
  };

  Item make_item(const TargetNode& node) const {
    Item item;
    item.node = node;
    if (!node.is_leaf) {
      item.view = target_view(node.bounds, frame_);
      item.bound_r = view_bound_radius(item.view);
    }
    return item;
  }

  // Ball of A (centre in A) against a target leaf, answered in A.
  BallProximity leaf_answer(const TargetNode& leaf, const Eigen::Vector3d& c_A, double r) const {
    BallProximity p = target_.ball_proximity(leaf, R_BA_ * c_A + p_BA_, r);
    p.normal = frame_.R * p.normal;
    return p;
  }

  double bound(std::int32_t i, const Item& t, double prune_at) {
    ++stats_->bv_tests;
    const N& a = na_[i];
    const Eigen::Vector3d ca = load(a.c);
    if (t.node.is_leaf) return leaf_answer(t.node, ca, bound_radius(a)).distance;
    double lb = (t.view.c - ca).norm() - bound_radius(a) - t.bound_r;
    if (lb >= prune_at) return lb;
    lb = std::max(lb, detail::rss_gap(rss_view(a, Eigen::Matrix3d::Identity(), ca), t.view, -kInf));
    if (is_signed_) lb = std::max(lb, -(a.max_r + t.view.r));
    return lb;
  }

  bool open_a(std::int32_t i, const Item& t) const {
    if (is_leaf(na_[i])) return false;
    if (t.node.is_leaf) return true;
    return bound_radius(na_[i]) >= t.bound_r;
  }

  // The children to visit next, with their bounds, nearest first.
  struct Next {
    std::int32_t i;
    Item t;
    double lb;
  };

  int expand(std::int32_t i, const Item& t, double prune_at, std::array<Next, 8>& next) {
    int n = 0;
    if (open_a(i, t)) {
      for (std::int32_t c : {na_[i].first, na_[i].first + 1}) {
        next[static_cast<std::size_t>(n)] = Next{c, t, bound(c, t, prune_at)};
        ++n;
      }
    } else {
      TargetNode kids[ProximityTarget::kMaxChildren];
      const int count = target_.children(t.node, kids);
      for (int k = 0; k < count; ++k) {
        const Item item = make_item(kids[k]);
        next[static_cast<std::size_t>(n)] = Next{i, item, bound(i, item, prune_at)};
        ++n;
      }
    }
    std::sort(next.begin(), next.begin() + n,
              [](const Next& x, const Next& y) { return x.lb < y.lb; });
    return n;
  }

  void distance_recurse(std::int32_t i, const Item& t) {
    const N& a = na_[i];
    if (is_leaf(a) && t.node.is_leaf) {
      for (std::int32_t k = a.first; k < a.first + a.count; ++k) {
        const PackedSphere& s = sa_[k];
        ++stats_->leaf_tests;
        const Eigen::Vector3d c = load(s.c);
        const BallProximity p = leaf_answer(t.node, c, s.r);
        if (p.distance < best_.value) {
          best_.value = p.distance;
          best_.a = k;
          best_.b = t.node.primitive;
          best_.pa = c + p.normal * s.r;
          best_.pb = best_.pa + p.normal * p.distance;
          prune_at_ = threshold_(best_.value);
          if (stop_at_overlap_ && p.distance <= 0.0) {
            done_ = true;
            return;
          }
        }
      }
      return;
    }
    std::array<Next, 8> next;
    const int n = expand(i, t, prune_at_, next);
    for (int k = 0; k < n; ++k) {
      if (next[static_cast<std::size_t>(k)].lb < prune_at_)
        distance_recurse(next[static_cast<std::size_t>(k)].i, next[static_cast<std::size_t>(k)].t);
      if (done_) return;
    }
  }

  void collide_recurse(std::int32_t i, const Item& t) {
    const N& a = na_[i];
    if (is_leaf(a) && t.node.is_leaf) {
      for (std::int32_t k = a.first; k < a.first + a.count; ++k) {
        const PackedSphere& s = sa_[k];
        ++stats_->leaf_tests;
        const Eigen::Vector3d c = load(s.c);
        const BallProximity p = leaf_answer(t.node, c, s.r);
        if (p.distance > 0.0) continue;
        if (out_ != nullptr) {
          const Eigen::Vector3d pa = c + p.normal * s.r;
          const Eigen::Vector3d pb = pa + p.normal * p.distance;
          TreeContact contact;
          contact.p_WC = *X_WA_ * (0.5 * (pa + pb));
          contact.n_W = X_WA_->linear() * p.normal;
          contact.depth = -p.distance;
          contact.sphere_a = k;
          contact.primitive_b = t.node.primitive;
          out_->push_back(contact);
        }
        ++found_;
        if (found_ >= max_contacts_) {
          done_ = true;
          return;
        }
      }
      return;
    }
    std::array<Next, 8> next;
    const int n = expand(i, t, slack_, next);
    for (int k = 0; k < n; ++k) {
      if (next[static_cast<std::size_t>(k)].lb <= slack_)
        collide_recurse(next[static_cast<std::size_t>(k)].i, next[static_cast<std::size_t>(k)].t);
      if (done_) return;
    }
  }

  const N* na_;
  const PackedSphere* sa_;
  const ProximityTarget& target_;
  Frame frame_;
  Eigen::Matrix3d R_BA_;
  Eigen::Vector3d p_BA_;
  QueryStats* stats_ = nullptr;
  bool is_signed_ = false;
  bool stop_at_overlap_ = false;
  bool done_ = false;
  Threshold threshold_{0.0, 0.0};
  double prune_at_ = kInf;
  Best best_{kInf};
  std::size_t max_contacts_ = 1;
  std::size_t found_ = 0;
  std::vector<TreeContact>* out_ = nullptr;
  const Eigen::Isometry3d* X_WA_ = nullptr;
  double slack_ = 0.0;
};

template <class F>
void with_target_traversal(const Layout& la, const ProximityTarget& target, const Frame& frame,
                           F&& f) {
  if (la.kind == BoundingVolumeKind::rss) {
    TargetTraversal<RssNode> t(la, target, frame);
    f(t, tree_extent<RssNode>(la));
  } else {
    TargetTraversal<BallNode> t(la, target, frame);
    f(t, tree_extent<BallNode>(la));
  }
}

TreeDistance target_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const ProximityTarget& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options, bool stop_at_overlap) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  check_options(options);
  const Layout* la = tree_layout(a);
  TreeDistance out;
  out.distance = options.upper_bound;
  if (la == nullptr || la->num_nodes == 0) return out;
  const std::optional<TargetNode> root = b.root();
  if (!root) return out;
  const Frame frame(X_WA, X_WB);
  QueryStats stats;
  Best best{options.upper_bound};
  with_target_traversal(*la, b, frame, [&](auto& t, double) {
    best = t.distance(*root, options, stop_at_overlap, stats);
  });
  return finish(best, *la, nullptr, X_WA, stats);
}

}  // namespace

TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                      const Eigen::Isometry3d& X_WB, const DistanceOptions& options) {
  return tree_distance(a, X_WA, b, X_WB, options, true);
}

TreeDistance signed_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const SphereTree& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options) {
  return tree_distance(a, X_WA, b, X_WB, options, false);
}

bool collide(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
             const Eigen::Isometry3d& X_WB, QueryStats* stats) {
  return tree_contacts(a, X_WA, b, X_WB, 1, nullptr, stats) > 0;
}

std::size_t contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA, const SphereTree& b,
                     const Eigen::Isometry3d& X_WB, std::size_t max_contacts,
                     std::vector<TreeContact>& out, QueryStats* stats) {
  return tree_contacts(a, X_WA, b, X_WB, max_contacts, &out, stats);
}

TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                      const Eigen::Vector3d& p_WQ, const DistanceOptions& options) {
  check_pose(X_WA, "X_WA");
  check_options(options);
  if (!p_WQ.allFinite()) throw std::invalid_argument("p_WQ has a non-finite coordinate");
  const Layout* la = tree_layout(a);
  TreeDistance out;
  out.distance = options.upper_bound;
  if (la == nullptr || la->num_nodes == 0) return out;
  const Eigen::Vector3d q = X_WA.inverse() * p_WQ;
  const Eigen::Vector3d x_W = X_WA.linear().transpose().col(0);
  QueryStats stats;
  Best best{options.upper_bound};
  if (la->kind == BoundingVolumeKind::rss)
    best = PointTraversal<RssNode>(*la, q, x_W).run(options, stats);
  else
    best = PointTraversal<BallNode>(*la, q, x_W).run(options, stats);
  out = finish(best, *la, nullptr, X_WA, stats);
  if (out.found()) out.p_WPb = p_WQ;
  return out;
}

TreeDistance distance(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                      const Eigen::Isometry3d& X_WB, const DistanceOptions& options) {
  return target_distance(a, X_WA, b, X_WB, options, true);
}

TreeDistance signed_distance(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                             const ProximityTarget& b, const Eigen::Isometry3d& X_WB,
                             const DistanceOptions& options) {
  return target_distance(a, X_WA, b, X_WB, options, false);
}

namespace {

std::size_t target_contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA,
                            const ProximityTarget& b, const Eigen::Isometry3d& X_WB,
                            std::size_t max_contacts, std::vector<TreeContact>* out,
                            QueryStats* stats) {
  check_pose(X_WA, "X_WA");
  check_pose(X_WB, "X_WB");
  const Layout* la = tree_layout(a);
  QueryStats local;
  std::size_t found = 0;
  const std::optional<TargetNode> root =
      (max_contacts > 0 && la != nullptr && la->num_nodes > 0) ? b.root() : std::nullopt;
  if (root) {
    const Frame frame(X_WA, X_WB);
    const double extent_b = root->is_leaf
                                ? 0.0
                                : (root->bounds.center().norm() + root->bounds.length.norm() * 0.5 +
                                   root->bounds.radius);
    const std::size_t before = out != nullptr ? out->size() : 0;
    with_target_traversal(*la, b, frame, [&](auto& t, double extent_a) {
      t.collide(*root, max_contacts, out, collision_slack(extent_a, extent_b, frame), X_WA, local,
                found);
    });
    if (out != nullptr) {
      for (std::size_t k = before; k < out->size(); ++k)
        (*out)[k].sphere_a = la->original_index[(*out)[k].sphere_a];
    }
  }
  if (stats != nullptr) *stats = local;
  return found;
}

}  // namespace

bool collide(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
             const Eigen::Isometry3d& X_WB, QueryStats* stats) {
  return target_contacts(a, X_WA, b, X_WB, 1, nullptr, stats) > 0;
}

std::size_t contacts(const SphereTree& a, const Eigen::Isometry3d& X_WA, const ProximityTarget& b,
                     const Eigen::Isometry3d& X_WB, std::size_t max_contacts,
                     std::vector<TreeContact>& out, QueryStats* stats) {
  return target_contacts(a, X_WA, b, X_WB, max_contacts, &out, stats);
}

}  // namespace medspheres
