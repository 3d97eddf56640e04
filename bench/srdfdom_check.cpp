// bench_srdfdom: MoveIt's own SRDF parser (moveit/srdfdom, srdf::Model) on the SRDF that
// `medspheres robot` writes, with the URDF read by urdfdom, as MoveIt reads them. Checks that
// it loads the file with no error or warning, and that what it reads is what the robot file
// means: every disabled pair with its reason (srdf_disabled_pairs) and every link's spheres
// (robot_spheres, the covering sets) to the last bit. urdfdom's warnings on the URDF are
// printed and counted apart: they are the URDF's. Prints one line per check; exit 0 when
// all hold, 1 when one does not, 2 for bad input. Built only when MEDSPHERES_SRDFDOM_DIR names
// a checkout (bench/CMakeLists.txt); CI has none.
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <console_bridge/console.h>
#include <srdfdom/model.h>
#include <urdf_parser/urdf_parser.h>

#include "bench_args.h"
#include "medspheres/error.h"
#include "medspheres/formats/planner_options.h"
#include "medspheres/formats/robot_spheres.h"
#include "medspheres/robot_file.h"

namespace {

namespace formats = medspheres::formats;

// Counts srdfdom's and urdfdom's errors and warnings (console_bridge), and prints them.
class Counter : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char* file,
           int line) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_WARN) return;
    ++count;
    std::printf("  console_bridge %s: %s (%s:%d)\n",
                level == console_bridge::CONSOLE_BRIDGE_LOG_WARN ? "warning" : "error",
                text.c_str(), file, line);
  }
  int count = 0;
};

using Pair = std::tuple<std::string, std::string, std::string>;  // link1 < link2, reason

Pair ordered(const std::string& a, const std::string& b, const std::string& reason) {
  return a < b ? Pair{a, b, reason} : Pair{b, a, reason};
}

// srdfdom's disabled pairs against the robot file's skipped pairs.
bool same_pairs(const srdf::Model& srdf, const std::vector<formats::DisabledCollision>& meant) {
  std::set<Pair> read, expected;
  for (const srdf::Model::CollisionPair& p : srdf.getDisabledCollisionPairs())
    read.insert(ordered(p.link1_, p.link2_, p.reason_));
  for (const formats::DisabledCollision& p : meant)
    expected.insert(ordered(p.link1, p.link2, p.reason));
  std::map<std::string, int> reasons;
  for (const Pair& p : read) ++reasons[std::get<2>(p)];
  std::printf("disabled pairs: srdfdom read %zu, the robot file skips %zu;", read.size(),
              expected.size());
  for (const auto& [reason, n] : reasons) std::printf(" %s %d", reason.c_str(), n);
  const bool same = read == expected && read.size() == srdf.getDisabledCollisionPairs().size();
  std::printf("; %s\n", same ? "the same pairs and reasons" : "DIFFERENT");
  return same;
}

// srdfdom's sphere approximations against the robot file's covering sets, bit for bit.
bool same_spheres(const srdf::Model& srdf, const formats::RobotSpheres& meant) {
  std::map<std::string, const formats::LinkSphereList*> by_link;
  std::size_t expected = 0, read = 0, differ = 0;
  for (const formats::LinkSphereList& l : meant) {
    by_link[l.link] = &l;
    expected += l.spheres.size();
  }
  std::size_t links = 0;
  for (const srdf::Model::LinkSpheres& l : srdf.getLinkSphereApproximations()) {
    ++links;
    const auto it = by_link.find(l.link_);
    // srdfdom keeps a lone sphere of radius 0, which means "none".
    std::vector<srdf::Model::Sphere> spheres = l.spheres_;
    if (spheres.size() == 1 && spheres[0].radius_ == 0.0) spheres.clear();
    read += spheres.size();
    if (it == by_link.end() || it->second->spheres.size() != spheres.size()) {
      ++differ;
      continue;
    }
    for (std::size_t i = 0; i < spheres.size(); ++i) {
      const medspheres::Sphere& s = it->second->spheres[i];
      const srdf::Model::Sphere& r = spheres[i];
      if (r.center_x_ != s.center.x() || r.center_y_ != s.center.y() ||
          r.center_z_ != s.center.z() || r.radius_ != s.radius)
        ++differ;
    }
  }
  const bool same = differ == 0 && links == meant.size() && read == expected;
  std::printf(
      "sphere approximations: srdfdom read %zu links, %zu spheres; the robot file "
      "has %zu links, %zu spheres; %zu differ; %s\n",
      links, read, meant.size(), expected, differ,
      same ? "the same spheres to the bit" : "DIFFERENT");
  return same;
}

int run(const std::string& urdf_path, const std::string& srdf_path, const std::string& robot_path,
        Counter& counter) {
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDFFile(urdf_path);
  if (!urdf) {
    std::printf("urdfdom could not read %s\n", urdf_path.c_str());
    return 2;
  }
  // urdfdom's own warnings are the URDF's (an undefined material, ...), not the SRDF's.
  std::printf("urdfdom::parseURDFFile(%s): %d errors or warnings\n", urdf_path.c_str(),
              counter.count);
  counter.count = 0;
  srdf::Model srdf;
  const bool loaded = srdf.initFile(*urdf, srdf_path);
  std::printf("srdf::Model::initFile(%s): %s, %d errors or warnings\n", srdf_path.c_str(),
              loaded ? "true" : "false", counter.count);
  if (!loaded) return 1;
  const medspheres::RobotModel model = medspheres::load_robot(robot_path);
  const formats::RobotSpheres spheres = formats::robot_spheres(model);
  const bool pairs = same_pairs(srdf, formats::srdf_disabled_pairs(model, spheres));
  const bool balls = same_spheres(srdf, spheres);
  const bool ok = counter.count == 0 && pairs && balls;
  std::printf("%s\n", ok ? "OK" : "FAILED");
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  medspheres::bench::Args args("bench_srdfdom",
                               "MoveIt's SRDF parser (srdfdom) on the SRDF of `medspheres robot`");
  CLI::App& app = args.app();
  std::string urdf, srdf, robot;
  app.add_option("urdf", urdf, "The robot's URDF")->required()->check(CLI::ExistingFile);
  app.add_option("srdf", srdf, "NAME.srdf written by medspheres robot")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("robot", robot, "NAME.robot.json written with it")
      ->required()
      ->check(CLI::ExistingFile);
  args.parse(argc, argv);
  static Counter counter;  // console_bridge keeps the handler until exit
  console_bridge::useOutputHandler(&counter);
  try {
    return run(urdf, srdf, robot, counter);
  } catch (const medspheres::InputError& e) {
    std::fprintf(stderr, "bench_srdfdom: %s\n", e.what());
    return 2;
  }
}
