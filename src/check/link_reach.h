#pragma once
// Where each link can be, whatever the configuration: a ball that holds the link's bounding
// sphere at every angle of its revolute joints, and the links whose ball stays clear of a
// scene, whose scene tests the checker can then skip outright.
//
// A revolute step puts a point y of its frame F at X_PF y = M Rot(a, q) y + u in its parent P
// (robot_layout.h: R(q) = P + cos q C + sin q S, with P = M a a^T and C = M (I - a a^T)).
// Rot(a, q) keeps y's part along a and turns the rest, so over every q the points of the
// ball (y0, rho) stay within the ball of centre P y0 + u and radius |C y0| + rho (the circle
// that y0 runs on, widened by rho). Applied from the link's frame up to W, step by step, this
// bounds the link's bounding sphere for every configuration. A prismatic joint's offset is
// unbounded (configurations go to 1e6): the links below one have no ball.

#include <vector>

#include <Eigen/Core>

#include "robot_layout.h"
#include "scene_grid.h"

namespace medspheres::check::detail {

struct LinkReach {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // in W
  double radius = 0.0;                               // infinite: no ball (a prismatic joint)
};

/// Per link of the layout (its links with geometry), in its order.
std::vector<LinkReach> link_reach(const RobotLayout& layout);

/// Per link of the layout: 1 when no element of the grid lies within its reach's radius plus
/// \p distance of its reach's centre (the grid's bound, else exact element distances), else 0.
std::vector<unsigned char> links_far_from_scene(const RobotLayout& layout, const SceneGrid& grid,
                                                double distance);

}  // namespace medspheres::check::detail
