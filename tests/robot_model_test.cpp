#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/robot_model.h"
#include "support/robot_fixtures.h"

using Catch::Matchers::Contains;
using medspheres::InputError;
using medspheres::JointType;
using medspheres::RobotModel;
using medspheres::test::make_joint;
using medspheres::test::make_link;
using medspheres::test::three_link_arm;

namespace {

std::string problem(const RobotModel& m) {
  try {
    medspheres::validate_robot_model(m, "arm.robot.json");
  } catch (const InputError& e) {
    CHECK(e.source() == "arm.robot.json");
    return e.problem();
  }
  return "";
}

}  // namespace

TEST_CASE("a valid tree passes and find_link/find_joint find by name", "[robot_model]") {
  const RobotModel m = three_link_arm();
  CHECK(problem(m).empty());
  REQUIRE(m.find_link("l2"));
  CHECK(m.find_link("l2")->name == "l2");
  CHECK(m.find_link("l9") == nullptr);
  REQUIRE(m.find_joint("j3"));
  CHECK(m.find_joint("j3")->mimic->joint == "j1");
  CHECK(m.find_joint("j9") == nullptr);
}

TEST_CASE("validation names the link or joint and the problem", "[robot_model]") {
  SECTION("a cycle through every link") {
    RobotModel m;
    m.links = {make_link("a"), make_link("b")};
    m.joints = {make_joint("ab", JointType::kFixed, "a", "b", {0, 0, 0}),
                make_joint("ba", JointType::kFixed, "b", "a", {0, 0, 0})};
    CHECK_THAT(problem(m), Contains("cycle"));
  }
  SECTION("a cycle beside the root") {
    RobotModel m = three_link_arm();
    m.links.push_back(make_link("x"));
    m.links.push_back(make_link("y"));
    m.joints.push_back(make_joint("xy", JointType::kFixed, "x", "y", {0, 0, 0}));
    m.joints.push_back(make_joint("yx", JointType::kFixed, "y", "x", {0, 0, 0}));
    CHECK_THAT(problem(m), Contains("cycle") && Contains("link \"x\""));
  }
  SECTION("two parents") {
    RobotModel m = three_link_arm();
    m.joints.push_back(make_joint("again", JointType::kFixed, "base", "l2", {0, 0, 0}));
    CHECK_THAT(problem(m), Contains("link \"l2\" has two parents") && Contains("\"again\""));
  }
  SECTION("two roots") {
    RobotModel m = three_link_arm();
    m.links.push_back(make_link("loose"));
    CHECK_THAT(problem(m), Contains("\"loose\"") && Contains("not one tree"));
  }
  SECTION("unknown mimic source") {
    RobotModel m = three_link_arm();
    m.joints[2].mimic->joint = "ghost";
    CHECK_THAT(problem(m), Contains("joint \"j3\" mimics the joint \"ghost\""));
  }
  SECTION("a loop of mimic joints") {
    RobotModel m = three_link_arm();
    m.joints[0].mimic = medspheres::JointMimic{"j3", 1.0, 0.0};  // j1 -> j3 -> j1
    CHECK_THAT(problem(m), Contains("loop"));
  }
  SECTION("unknown link, duplicate names, wrong root, zero axis, bad limits, bad spheres") {
    RobotModel m = three_link_arm();
    m.joints[0].child = "nowhere";
    CHECK_THAT(problem(m), Contains("joint \"j1\" names the link \"nowhere\""));
    m = three_link_arm();
    m.links.push_back(make_link("l1"));
    CHECK_THAT(problem(m), Contains("link \"l1\" is defined twice"));
    m = three_link_arm();
    m.joints[1].name = "j1";
    CHECK_THAT(problem(m), Contains("joint \"j1\" is defined twice"));
    m = three_link_arm();
    m.root_link = "l1";
    CHECK_THAT(problem(m), Contains("root link is \"l1\""));
    m = three_link_arm();
    m.joints[1].axis.setZero();
    CHECK_THAT(problem(m), Contains("joint \"j2\": the axis is zero"));
    m = three_link_arm();
    m.joints[0].limits->lower = 4.0;
    CHECK_THAT(problem(m), Contains("joint \"j1\": the lower limit"));
    m = three_link_arm();
    m.links[2].spheres.outer.spheres.push_back({{0, 0, 0}, -1.0});
    CHECK_THAT(problem(m), Contains("link \"l2\" outer set"));
  }
}
