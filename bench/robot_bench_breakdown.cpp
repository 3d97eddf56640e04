// bench_robot --breakdown (robot_bench_breakdown.h).

#include "robot_bench_breakdown.h"

#include <cstdio>
#include <string>

#include "bench_timing.h"

namespace medspheres::bench {
namespace {

// The kind of a scene object, by the name the scene gave it.
std::string kind_of(const std::string& name) {
  if (name.rfind("mesh", 0) == 0) return "meshes";
  if (name == "octomap") return "octomap";
  return "boxes";
}

// CPU microseconds per configuration of f(X) over every configuration; f's counts summed.
template <class F>
double micros_per_config(const std::vector<std::vector<::fcl::Transform3d>>& poses, F&& f,
                         std::size_t& count) {
  const double t0 = thread_cpu_micros();
  for (const auto& X : poses) count += f(X);
  return (thread_cpu_micros() - t0) / static_cast<double>(poses.size());
}

}  // namespace

void print_breakdown(const std::vector<std::vector<::fcl::Transform3d>>& poses,
                     const BenchScene& scene, std::size_t links, std::size_t self_pairs,
                     ExactRobot& exact, const SphereRobot& outer, const SphereRobot& inner,
                     bool self, double margin) {
  const std::vector<const ::fcl::CollisionObjectd*> objects = scene.pointers();
  const double n = static_cast<double>(poses.size());
  std::printf(
      "\nwhere the time goes: every pair of a kind at every configuration, no stop (a free "
      "configuration's cost), CPU time\n");
  std::printf("%-8s %10s %10s %10s %10s %10s\n", "kind", "pairs", "within", "exact us", "outer us",
              "inner us");
  for (const char* kind : {"boxes", "meshes", "octomap", "self"}) {
    const bool is_self = std::string(kind) == "self";
    if (is_self && !self) continue;
    std::vector<char> use(objects.size(), 0);
    std::size_t count = 0;
    for (std::size_t o = 0; o < objects.size() && !is_self; ++o)
      if (kind_of(scene.objects[o].name) == kind) {
        use[o] = 1;
        ++count;
      }
    if (!is_self && count == 0) continue;
    std::size_t within = 0, ignored = 0;
    const double te = micros_per_config(
        poses, [&](const auto& X) { return exact.pairs_within(X, use, is_self, margin); }, within);
    const double to = micros_per_config(
        poses, [&](const auto& X) { return outer.within(X, objects, use, is_self, margin, false); },
        ignored);
    const double ti = micros_per_config(
        poses, [&](const auto& X) { return inner.within(X, objects, use, is_self, margin, false); },
        ignored);
    const double pairs = static_cast<double>(is_self ? self_pairs : links * count);
    std::printf("%-8s %10.0f %10.3f %10.2f %10.2f %10.2f\n", kind, pairs,
                static_cast<double>(within) / n, te, to, ti);
  }
}

}  // namespace medspheres::bench
