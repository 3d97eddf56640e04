#pragma once
// bench_robot's sphere-set methods: one sphere set per link (inner or outer) as an FCL
// geometry, every pair checked within the margin by medspheres::fcl::distance with the
// margin preset as min_distance (the drop-in path, as MoveIt calls FCL).

#include <cstddef>
#include <memory>
#include <vector>

#include <fcl/narrowphase/collision_object.h>

#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/fcl/sphere_set_geometry.h"
#include "medspheres/robot_model.h"

namespace medspheres::bench {

class SphereRobot {
 public:
  /// The inner (\p inner) or outer sets of the links of \p robot, from \p model.
  SphereRobot(const fcl::RobotBounds& robot, const RobotModel& model, bool inner);

  /// The pairs within \p margin at the link poses X (RobotBounds::poses): every link against
  /// the scene objects whose entry of \p use is set (all of them when \p use is empty), then
  /// the self pairs when \p self; with \p stop, up to the first pair within the margin.
  /// Returns how many pairs it found within the margin.
  std::size_t within(const std::vector<::fcl::Transform3d>& X,
                     const std::vector<const ::fcl::CollisionObjectd*>& scene,
                     const std::vector<char>& use, bool self, double margin, bool stop) const;

  /// Whether some pair is within the margin: the scene first, then the self pairs.
  bool collide(const std::vector<::fcl::Transform3d>& X,
               const std::vector<const ::fcl::CollisionObjectd*>& scene, bool self,
               double margin) const {
    return within(X, scene, {}, self, margin, true) > 0;
  }

 private:
  const fcl::RobotBounds& robot_;
  std::vector<std::shared_ptr<fcl::SphereSetGeometry>> sets_;
};

}  // namespace medspheres::bench
