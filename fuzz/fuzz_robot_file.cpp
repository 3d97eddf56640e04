// The robot file reader (robot_file.h). Oracles: an accepted model is a tree that forward
// kinematics accepts and walks (poses may overflow to infinity for origins near the
// largest double, which is no error), and write after read is a fixed point.
#include <Eigen/Core>

#include "fuzz_support.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/robot_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres;
  RobotModel model;
  if (!fuzz::accepts([&] { model = parse_robot(fuzz::text_of(data, size), "fuzz.robot.json"); }))
    return 0;
  const KinematicTree tree(model, "fuzz.robot.json");
  const Eigen::VectorXd q =
      Eigen::VectorXd::Constant(static_cast<Eigen::Index>(tree.num_positions()), 0.5);
  MEDSPHERES_FUZZ_CHECK(tree.link_poses(q).size() == model.links.size());
  const std::string once = robot_to_json(model);
  const std::string twice = robot_to_json(parse_robot(once, "written.robot.json"));
  MEDSPHERES_FUZZ_CHECK(once == twice);
  return 0;
}
