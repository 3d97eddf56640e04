#pragma once
// Top-down construction shared by SphereTree and TriangleTree: the PCA split of paper
// §5.2 and the RSS fit of Larsen et al. to a set of balls (their minimum enclosing ball:
// medspheres/min_enclosing_ball.h). Private to the runtime target.

#include <vector>

#include <Eigen/Core>

#include "medspheres/rss.h"
#include "medspheres/sphere_set.h"

namespace medspheres::detail {

/// A closed ball; radius 0 makes it a point (a triangle is fitted as its three corners).
using Ball = Sphere;

/// One node of a hierarchy under construction.
struct BuildNode {
  int begin = 0;  ///< items order[begin, end) lie below the node
  int end = 0;
  int first_child = -1;  ///< -1 for a leaf; otherwise the children are first_child and +1
  int depth = 0;         ///< edges from the root
  /// PCA axes of the balls below the node: major, middle, and their cross product.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};

/// The input of build_hierarchy: item i owns balls[ball_begin[i] .. ball_begin[i + 1])
/// and is sorted into a child by its split point.
struct BuildInput {
  std::vector<Eigen::Vector3d> split_points;
  std::vector<int> ball_begin;  ///< size items + 1
  std::vector<Ball> balls;
};

/// Builds the hierarchy top-down. Node 0 is the root; the two children of a node are
/// consecutive. \p order receives the item permutation: node n holds the items
/// order[n.begin .. n.end). A node with at most max_leaf_size items is a leaf.
std::vector<BuildNode> build_hierarchy(const BuildInput& input, int max_leaf_size,
                                       std::vector<int>& order);

/// The balls of the items order[begin .. end).
std::vector<Ball> balls_below(const BuildInput& input, const std::vector<int>& order, int begin,
                              int end);

/// The RSS with rectangle along axes.col(0) and axes.col(1) (swapped when that makes
/// length[0] >= length[1]) that contains every ball; see SphereTree::rss for the
/// rounding margin.
Rss fit_rss(const Eigen::Matrix3d& axes, const std::vector<Ball>& balls);

/// The largest value of dist(c, rectangle) + r over the balls, computed in double.
double rss_containment_radius(const Rss& rss, const std::vector<Ball>& balls);

}  // namespace medspheres::detail
