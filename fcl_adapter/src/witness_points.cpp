#include "witness_points.h"

#include <tuple>

namespace medspheres::fcl::detail {

std::map<std::string, std::vector<Sphere>> witness_points(const RobotModel& planner,
                                                          const RobotBounds& bounds) {
  using Key = std::tuple<double, double, double, double>;
  std::map<std::string, std::map<Key, Sphere>> by_link;
  auto add = [&](std::size_t g, const Sphere& s) {
    const std::string& name = bounds.geometries()[g].link();
    const Link* link = planner.find_link(name);
    if (link == nullptr || link->spheres.outer.empty()) return;
    by_link[name].emplace(Key{s.center.x(), s.center.y(), s.center.z(), s.radius}, s);
  };
  for (const SelfWitness& w : bounds.witnesses()) {
    add(w.a, w.in_a);
    add(w.b, w.in_b);
  }
  std::map<std::string, std::vector<Sphere>> out;
  for (const auto& [name, spheres] : by_link)
    for (const auto& [key, s] : spheres) out[name].push_back(s);
  return out;
}

}  // namespace medspheres::fcl::detail
