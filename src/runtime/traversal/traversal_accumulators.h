#pragma once
// What the traversal (traversal.h) gathers: the closest pair of a distance query, or the
// overlapping pairs of a collision query, with the QueryStats of the walk. Positions are
// in the query's frame A until a contact is stored. Private to the runtime target.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "medspheres/sphere_tree.h"

namespace medspheres::detail {

/// The pruning rule of FCL's distance traversals: a lower bound c is pruned when
/// c >= best - abs_err and c (1 + rel_err) >= best, i.e. when c >= (*this)(best).
struct Threshold {
  double abs_err;
  double rel_err;
  double operator()(double best) const { return std::max(best - abs_err, best / (1.0 + rel_err)); }
};

/// The smallest signed distance offered, below options.upper_bound; with
/// stop_at_overlap, the first pair offered at distance <= 0 ends the walk.
class ClosestPair {
 public:
  ClosestPair(const DistanceOptions& options, bool stop_at_overlap)
      : threshold_{options.abs_err, options.rel_err},
        stop_at_overlap_(stop_at_overlap),
        value_(options.upper_bound),
        prune_at_(threshold_(value_)) {}

  QueryStats stats;

  double prune_at() const { return prune_at_; }
  bool keeps(double lb) const { return lb < prune_at_; }
  bool done() const { return done_; }

  /// The best signed distance so far; a leaf test offers only pairs below it.
  double value() const { return value_; }

  /// Records pair (a, b) at signed distance sd < value(), with its witness points in A.
  void offer(double sd, std::int32_t a, std::intptr_t b, const Eigen::Vector3d& pa,
             const Eigen::Vector3d& pb) {
    value_ = sd;
    a_ = a;
    b_ = b;
    pa_ = pa;
    pb_ = pb;
    prune_at_ = threshold_(value_);
    if (stop_at_overlap_ && sd <= 0.0) done_ = true;
  }

  /// The result in W: indices mapped through the trees' original_index (B's only when
  /// \p original_b is given; a target's primitive ids are reported as they are).
  TreeDistance result(const std::int32_t* original_a, const std::int32_t* original_b,
                      const Eigen::Isometry3d& X_WA) const {
    TreeDistance out;
    out.distance = value_;
    out.stats = stats;
    if (a_ >= 0) {
      out.sphere_a = original_a[a_];
      out.primitive_b = original_b != nullptr ? original_b[b_] : b_;
      out.p_WPa = X_WA * pa_;
      out.p_WPb = X_WA * pb_;
    }
    return out;
  }

 private:
  Threshold threshold_;
  bool stop_at_overlap_;
  double value_;
  double prune_at_;
  bool done_ = false;
  std::int32_t a_ = -1;   // tree position of the sphere of A
  std::intptr_t b_ = -1;  // tree position of the sphere of B, or the primitive id
  Eigen::Vector3d pa_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d pb_ = Eigen::Vector3d::Zero();
};

/// Up to max_contacts (>= 1) overlapping pairs, in the order offered, appended to *out
/// (when out is not null) as contacts in W. Pairs whose bound is at most slack are
/// visited: slack >= 0 absorbs the rounding of the bounds, so that touching pairs are
/// never pruned.
class ContactList {
 public:
  ContactList(std::size_t max_contacts, std::vector<TreeContact>* out, double slack,
              const Eigen::Isometry3d& X_WA)
      : max_contacts_(max_contacts), out_(out), slack_(slack), X_WA_(X_WA) {}

  QueryStats stats;

  double prune_at() const { return slack_; }
  bool keeps(double lb) const { return lb <= slack_; }
  bool done() const { return done_; }
  std::size_t found() const { return found_; }

  /// Records an overlapping pair (a, b) (sphere_a and primitive_b as given): witness
  /// points pa, pb and unit normal n from a to b in A, signed distance sd <= 0.
  void offer(double sd, std::intptr_t a, std::intptr_t b, const Eigen::Vector3d& pa,
             const Eigen::Vector3d& pb, const Eigen::Vector3d& n) {
    if (out_ != nullptr) {
      TreeContact c;
      c.p_WC = X_WA_ * (0.5 * (pa + pb));
      c.n_W = X_WA_.linear() * n;
      c.depth = -sd;
      c.sphere_a = a;
      c.primitive_b = b;
      out_->push_back(c);
    }
    ++found_;
    if (found_ >= max_contacts_) done_ = true;
  }

 private:
  std::size_t max_contacts_;
  std::vector<TreeContact>* out_;
  double slack_;
  const Eigen::Isometry3d& X_WA_;
  std::size_t found_ = 0;
  bool done_ = false;
};

}  // namespace medspheres::detail
