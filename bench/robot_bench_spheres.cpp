// bench_robot's sphere-set methods (robot_bench_spheres.h).

#include "robot_bench_spheres.h"

#include <cmath>
#include <limits>

namespace medspheres::bench {

SphereRobot::SphereRobot(const fcl::RobotBounds& robot, const RobotModel& model, bool inner)
    : robot_(robot) {
  for (const fcl::BoundedGeometry& g : robot.geometries()) {
    const LinkSpheres& s = model.find_link(g.link())->spheres;
    sets_.push_back(std::make_shared<fcl::SphereSetGeometry>(inner ? s.inner : s.outer));
  }
}

std::size_t SphereRobot::within(const std::vector<::fcl::Transform3d>& X,
                                const std::vector<const ::fcl::CollisionObjectd*>& scene,
                                const std::vector<char>& use, bool self, double margin,
                                bool stop) const {
  const double above = std::nextafter(margin, std::numeric_limits<double>::infinity());
  auto near = [&](const ::fcl::CollisionGeometryd* a, const ::fcl::Transform3d& Xa,
                  const ::fcl::CollisionGeometryd* b, const ::fcl::Transform3d& Xb) {
    ::fcl::DistanceRequestd request;
    ::fcl::DistanceResultd result;
    result.min_distance = above;  // only a pair within the margin replaces it
    return fcl::distance(a, Xa, b, Xb, request, result) < above;
  };
  std::size_t found = 0;
  for (std::size_t l = 0; l < sets_.size(); ++l)
    for (std::size_t o = 0; o < scene.size(); ++o) {
      if (!use.empty() && !use[o]) continue;
      if (!near(sets_[l].get(), X[l], scene[o]->collisionGeometry().get(),
                scene[o]->getTransform()))
        continue;
      ++found;
      if (stop) return found;
    }
  if (self)
    for (const auto& [a, b] : robot_.self_pairs()) {
      if (!near(sets_[a].get(), X[a], sets_[b].get(), X[b])) continue;
      ++found;
      if (stop) return found;
    }
  return found;
}

}  // namespace medspheres::bench
