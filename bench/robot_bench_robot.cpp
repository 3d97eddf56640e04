// bench_robot's robot: URDF, link meshes, and sphere sets from a robot file, the cache or
// a fresh bake (robot_bench_robot.h).

#include "robot_bench_robot.h"

#include <cstdio>
#include <filesystem>

#include "bench_util.h"
#include "medspheres/batch/batch_robot.h"
#include "medspheres/error.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_file.h"
#include "medspheres/sha256.h"

namespace medspheres::bench {
namespace fs = std::filesystem;

namespace {

// The bake: the robot command's defaults, with outer sets and the source's budget.
RobotJob bake_job(const RobotSource& source) {
  RobotJob job;
  job.bake.jobs = source.jobs;
  job.bake.budget.per_link = source.spheres_per_link;
  job.bake.outer = true;
  return job;
}

// The sets for the URDF's links, and a line saying where they came from.
RobotModel robot_sets(const UrdfRobot& robot, const std::vector<LinkSolid>& solids,
                      const RobotSource& source, std::string& from) {
  if (!source.robot_file.empty()) {
    RobotModel m = load_robot(source.robot_file);
    require_same_links(m, robot, source.robot_file);
    from = "robot file " + source.robot_file;
    return m;
  }
  const RobotJob job = bake_job(source);
  // The batch cache's key (batch_robot.h): the URDF, its meshes' bytes, the bake and the
  // library's version.
  const std::string key = robot_cache_key(robot, file_sha256(robot.path), job,
                                          fs::path(robot.path).filename().string());
  const fs::path cached = fs::path(source.cache_dir) / (key + ".robot.json");
  if (!source.cache_dir.empty() && fs::exists(cached)) {
    from = "cached bake " + cached.string();
    return load_robot(cached.string());
  }
  const auto t0 = std::chrono::steady_clock::now();
  RobotModel m = bake_robot(robot, solids, job.bake).model;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  char text[64];
  std::snprintf(text, sizeof text, "baked in %.1f s", s);
  from = text;
  if (!source.cache_dir.empty()) {
    fs::create_directories(source.cache_dir);
    save_robot(m, cached.string());
    from += ", cached as " + cached.string();
  }
  return m;
}

}  // namespace

BenchRobot load_bench_robot(const RobotSource& source) {
  UrdfReadOptions read;
  for (const std::string& p : source.packages) add_package_dir(read.packages, p);
  const UrdfRobot robot = read_urdf(source.urdf, read);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  BenchRobot out;
  out.model = robot_sets(robot, solids, source, out.spheres_from);
  for (const LinkSolid& s : solids) {
    if (s.empty()) continue;
    ExactLink& exact = out.exact[s.link];
    exact.spheres = s.spheres;
    if (s.parts.empty()) continue;
    const TriangleMesh mesh = s.placed_mesh();
    out.triangles += mesh.triangles.size();
    exact.mesh = out.meshes[s.link] = make_bvh<::fcl::OBBRSSd>(mesh);
    out.solids[exact.mesh.get()] = std::make_shared<MeshQuery>(mesh);
  }
  return out;
}

}  // namespace medspheres::bench
