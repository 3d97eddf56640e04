// The planner setup's plain data: tool frames by the gripper and branch rules, finger
// joints, the clamped zero pose, adjacency, the frames listed for cuRobo's tree, the robot
// file's round trip and the validation of every reference.
#include <algorithm>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/planner_setup.h"
#include "medspheres/robot_file.h"
#include "support/robot_fixtures.h"

using Catch::Matchers::Contains;
using namespace medspheres;
using medspheres::test::make_joint;
using medspheres::test::make_link;

namespace {

using Names = std::vector<std::string>;

// base -j1 (revolute)-> upper -j2 (revolute)-> lower -flange (fixed)-> wrist -tool_fixed->
// tcp, wrist -fl (prismatic)-> finger_l, wrist -fr (prismatic, mimic of fl)-> finger_r;
// base -j3 (revolute)-> cam (no other joint below it).
RobotModel gripper_arm() {
  RobotModel m;
  m.name = "g";
  m.root_link = "base";
  for (const char* n : {"base", "upper", "lower", "wrist", "tcp", "finger_l", "finger_r", "cam"})
    m.links.push_back(make_link(n));
  auto revolute = [&](const char* name, const char* p, const char* c, double lo, double hi) {
    m.joints.push_back(make_joint(name, JointType::kRevolute, p, c, {0, 0, 0.1}));
    m.joints.back().limits = JointLimits{lo, hi, 1, 1};
  };
  revolute("j1", "base", "upper", -2, 2);
  revolute("j2", "upper", "lower", 0.5, 2);  // limits that exclude 0
  m.joints.push_back(make_joint("flange", JointType::kFixed, "lower", "wrist", {0, 0, 0.1}));
  m.joints.push_back(make_joint("tool_fixed", JointType::kFixed, "wrist", "tcp", {0, 0, 0.1}));
  m.joints.push_back(make_joint("fl", JointType::kPrismatic, "wrist", "finger_l", {0, 0.01, 0}));
  m.joints.back().limits = JointLimits{0, 0.04, 1, 1};
  m.joints.push_back(make_joint("fr", JointType::kPrismatic, "wrist", "finger_r", {0, -0.01, 0}));
  m.joints.back().limits = JointLimits{0, 0.04, 1, 1};
  m.joints.back().mimic = JointMimic{"fl", 1.0, 0.0};
  revolute("j3", "base", "cam", -1, 1);
  return m;
}

}  // namespace

TEST_CASE("tool frames: per branch the link that carries the gripper, else the branch's end",
          "[planner]") {
  const RobotModel m = gripper_arm();
  std::string from;
  // The wrist carries the fingers (finger joints: prismatic, or mimic); "cam" ends the
  // other branch. Model link order.
  CHECK(default_tool_frames(m, &from) == Names{"wrist", "cam"});
  CHECK(from == "gripper");
  // Only the left finger's joint is actuated (the right one mimics it).
  CHECK(finger_joints(m, {"wrist"}) == Names{"fl"});
  CHECK(finger_joints(m, {"lower"}) == Names{"fl"});  // through the fixed flange
  CHECK(finger_joints(m, {"upper"}).empty());         // j2 moves between
  CHECK(finger_joints(m, {"cam"}).empty());

  // Without fingers: the frame fixed to a branch's end that is named as a tool frame is
  // (tcp), else the last link an arm joint moves.
  RobotModel bare = m;
  bare.joints.erase(bare.joints.begin() + 4, bare.joints.begin() + 6);
  bare.links.erase(bare.links.begin() + 5, bare.links.begin() + 7);
  CHECK(default_tool_frames(bare, &from) == Names{"tcp", "cam"});
  CHECK(from == "frame");
  bare.links[4].name = bare.joints[3].child = "mount";
  CHECK(default_tool_frames(bare, &from) == Names{"lower", "cam"});
  CHECK(from == "branch");
  // The three-link arm: j1 revolute, j2 prismatic (a finger joint), j3 mimic (finger): the
  // link l1 carries what only finger joints move.
  CHECK(default_tool_frames(test::three_link_arm(), &from) == Names{"l1"});
  CHECK(from == "gripper");
  // A telescoping arm: a prismatic joint (extend) between the wrist and the link that
  // carries the two fingers. The jaws' carrier is the tool frame, and extend stays a joint
  // of the arm (it is not locked with the fingers).
  RobotModel telescope = m;
  telescope.links.push_back(make_link("slide"));
  telescope.joints.push_back(
      make_joint("extend", JointType::kPrismatic, "wrist", "slide", {0, 0, 0.1}));
  telescope.joints.back().limits = JointLimits{0, 0.3, 1, 1};
  for (Joint& j : telescope.joints)
    if (j.name == "fl" || j.name == "fr") j.parent = "slide";
  CHECK(default_tool_frames(telescope, &from) == Names{"slide", "cam"});  // the gripper first
  CHECK(from == "gripper");
  CHECK(finger_joints(telescope, {"slide"}) == Names{"fl"});
  // One link, no joint: the root.
  RobotModel one;
  one.links.push_back(make_link("only"));
  CHECK(default_tool_frames(one, &from) == Names{"only"});
  CHECK(from == "root");
}

namespace {

// A chain of revolute joints from \p parent: links prefix1 .. prefixN, each joint's origin
// \p step from its parent (limits [-1, 1]; \p type for every joint).
void add_chain(RobotModel& m, const std::string& parent, const std::string& prefix, int n,
               const Eigen::Vector3d& step, JointType type = JointType::kRevolute) {
  std::string above = parent;
  for (int k = 1; k <= n; ++k) {
    const std::string link = prefix + std::to_string(k);
    m.links.push_back(make_link(link));
    m.joints.push_back(make_joint(link + "_joint", type, above, link, step));
    m.joints.back().limits = JointLimits{-1, 1, 1, 1};
    above = link;
  }
}

void add_fixed(RobotModel& m, const std::string& parent, const std::string& child) {
  m.links.push_back(make_link(child));
  m.joints.push_back(make_joint(child + "_joint", JointType::kFixed, parent, child, {0, 0, 0.02}));
}

// An arm of six revolute joints 0.2 m apart from "base", its last link "arm6".
RobotModel six_joint_arm() {
  RobotModel m;
  m.name = "six";
  m.root_link = "base";
  m.links.push_back(make_link("base"));
  add_chain(m, "base", "arm", 6, {0, 0, 0.2});
  return m;
}

}  // namespace

TEST_CASE("tool frames: flange frames by name, hands by their fingers' reach", "[planner]") {
  std::string from;
  // A UR-like flange: arm6 -> flange -> tool0 and flange -> camera_mount, all fixed.
  RobotModel ur = six_joint_arm();
  add_fixed(ur, "arm6", "flange");
  add_fixed(ur, "flange", "camera_mount");
  add_fixed(ur, "flange", "tool0");
  CHECK(default_tool_frames(ur, &from) == Names{"tool0"});
  CHECK(from == "frame");
  CHECK(finger_joints(ur, {"tool0"}).empty());
  // A Sawyer-like one: a head on a one-joint branch, first in link order, and the arm's
  // flange frame "right_hand". The longer chain's end comes first (a planner's primary
  // end effector); "hand" ranks last among the names.
  RobotModel sawyer = six_joint_arm();
  sawyer.links.insert(sawyer.links.begin() + 1, make_link("head"));
  sawyer.joints.push_back(
      make_joint("head_pan", JointType::kRevolute, "arm1", "head", {0, 0, 0.3}));
  sawyer.joints.back().limits = JointLimits{-1, 1, 1, 1};
  CHECK(default_tool_frames(sawyer, &from) == Names{"arm6", "head"});
  CHECK(from == "branch");
  add_fixed(sawyer, "arm6", "right_hand");
  CHECK(default_tool_frames(sawyer, &from) == Names{"right_hand", "head"});
  CHECK(from == "frame");
  add_fixed(sawyer, "arm6", "right_ee");
  CHECK(default_tool_frames(sawyer, &from) == Names{"right_ee", "head"});
  // A Kinova-like one: tool_frame ranks above end_effector_link, which is nearer.
  RobotModel kinova = six_joint_arm();
  add_fixed(kinova, "arm6", "end_effector_link");
  add_fixed(kinova, "end_effector_link", "camera_link");
  add_fixed(kinova, "end_effector_link", "Tool_Frame");
  CHECK(default_tool_frames(kinova, &from) == Names{"Tool_Frame"});

  // A Jaco-like hand: three fingers of two revolute joints each, 5 cm a joint.
  RobotModel jaco = six_joint_arm();
  add_fixed(jaco, "arm6", "end_effector");
  for (const char* f : {"a", "b", "c"})
    add_chain(jaco, "arm6", std::string("finger_") + f, 2, {0.02, 0, 0.05});
  CHECK(default_tool_frames(jaco, &from) == Names{"arm6"});
  CHECK(from == "gripper");
  CHECK(finger_joints(jaco, {"arm6"}) == Names{"finger_a1_joint", "finger_a2_joint",
                                               "finger_b1_joint", "finger_b2_joint",
                                               "finger_c1_joint", "finger_c2_joint"});
  // The same fingers 15 cm a joint reach beyond a hand's (kHandReach): legs, not fingers.
  RobotModel legs = six_joint_arm();
  for (const char* f : {"a", "b", "c"})
    add_chain(legs, "arm6", std::string("leg_") + f, 2, {0.02, 0, 0.15});
  CHECK(default_tool_frames(legs, &from) == Names{"leg_a2", "leg_b2", "leg_c2"});
  CHECK(from == "branch");
  CHECK(finger_joints(legs, {"leg_a2"}).empty());
  // Continuous joints are wheels, not fingers, however near.
  RobotModel wheels = six_joint_arm();
  for (const char* f : {"l", "r"})
    add_chain(wheels, "base", std::string("wheel_") + f, 1, {0, 0.1, 0}, JointType::kContinuous);
  CHECK(default_tool_frames(wheels, &from) == Names{"arm6", "wheel_l1", "wheel_r1"});

  // A Robotiq-like linkage: a revolute driver and three revolute joints that mimic it, all
  // on the gripper's base; the driver alone is locked.
  RobotModel robotiq = six_joint_arm();
  add_fixed(robotiq, "arm6", "gripper_base");
  for (const char* f : {"drive", "inner_l", "outer_r", "inner_r"})
    add_chain(robotiq, "gripper_base", f, 1, {0, 0.03, 0.05});
  for (std::size_t k = robotiq.joints.size() - 3; k < robotiq.joints.size(); ++k)
    robotiq.joints[k].mimic = JointMimic{"drive1_joint", 1.0, 0.0};
  add_fixed(robotiq, "gripper_base", "grasp_frame");
  CHECK(default_tool_frames(robotiq, &from) == Names{"gripper_base"});
  CHECK(from == "gripper");
  CHECK(finger_joints(robotiq, {"gripper_base"}) == Names{"drive1_joint"});
  // The same linkage with its followers typed continuous (as some Robotiq 2F descriptions
  // have them): followers, not wheels, so still a hand.
  for (std::size_t k = robotiq.joints.size() - 4; k < robotiq.joints.size() - 1; ++k)
    robotiq.joints[k].type = JointType::kContinuous;
  CHECK(default_tool_frames(robotiq, &from) == Names{"gripper_base"});
  CHECK(finger_joints(robotiq, {"gripper_base"}) == Names{"drive1_joint"});

  // A hand alone (the Jaco's fingers on a palm at the root) and a gripper alone: their
  // fingers are every joint a planner can move, so none is locked.
  RobotModel hand;
  hand.name = "hand";
  hand.root_link = "palm";
  hand.links.push_back(make_link("palm"));
  for (const char* f : {"a", "b", "c"})
    add_chain(hand, "palm", std::string("finger_") + f, 2, {0.02, 0, 0.05});
  CHECK(default_tool_frames(hand, &from) == Names{"palm"});
  CHECK(from == "gripper");
  CHECK(finger_joints(hand, {"palm"}).empty());
  RobotModel jaws = gripper_arm();
  jaws.joints.erase(jaws.joints.begin(), jaws.joints.begin() + 2);  // j1, j2
  jaws.joints.pop_back();                                           // j3
  jaws.links.erase(jaws.links.begin(), jaws.links.begin() + 2);     // base, upper
  jaws.links.pop_back();                                            // cam
  jaws.root_link = "lower";
  CHECK(finger_joints(jaws, {"wrist"}).empty());
  CHECK(finger_joints(gripper_arm(), {"wrist"}) == Names{"fl"});
}

TEST_CASE("the clamped zero pose, rigid bodies and adjacency over links with geometry",
          "[planner]") {
  const RobotModel m = gripper_arm();
  const auto zero = clamped_zero(m);
  CHECK(zero.size() == 4);  // j1, j2, fl, j3 (fr mimics)
  CHECK(zero.at("j1") == 0.0);
  CHECK(zero.at("j2") == 0.5);  // clamped into [0.5, 2]
  CHECK(zero.count("fr") == 0);
  // Geometry on base, lower, finger_l, finger_r: lower's nearest ancestor with geometry is
  // base (upper has none), the fingers' is lower (through wrist).
  const std::vector<bool> geometry{true, false, true, false, false, true, true, false};
  const auto adjacent = adjacent_link_pairs(m, geometry);
  using P = std::pair<std::size_t, std::size_t>;
  CHECK(adjacent == std::vector<P>{{0, 2}, {2, 5}, {2, 6}});
  // lower, wrist and tcp are one rigid body (fixed joints): wrist and tcp ride on lower,
  // which alone is the joint j2's; a finger's is the wrist, its parent.
  CHECK(rigid_bodies(m) == std::vector<std::size_t>{0, 1, 2, 2, 2, 5, 6, 7});
  const std::vector<bool> rigid_geometry{true, false, true, true, true, true, false, false};
  CHECK(adjacent_link_pairs(m, rigid_geometry) == std::vector<P>{{0, 2}, {3, 5}});
  CHECK(rigid_link_pairs(m, rigid_geometry) == std::vector<P>{{2, 3}, {2, 4}, {3, 4}});
  // A link without geometry whose rigid body has some stands for it: with geometry on tcp
  // alone in that body, the finger's parent (wrist) is represented by tcp.
  const std::vector<bool> tcp_only{true, false, false, false, true, true, false, false};
  CHECK(adjacent_link_pairs(m, tcp_only) == std::vector<P>{{0, 4}, {4, 5}});
}

TEST_CASE("listed tool frames: every actuated joint ends up in cuRobo's tree", "[planner]") {
  const RobotModel m = gripper_arm();
  const std::vector<bool> geometry{true, true, true, true, false, true, true, false};
  // j3 moves "cam", which has no spheres and is no tool frame: cam is listed after them.
  CHECK(listed_tool_frames(m, {"wrist"}, geometry) == Names{"wrist", "cam"});
  CHECK(listed_tool_frames(m, {"wrist", "cam"}, geometry) == Names{"wrist", "cam"});
  // With spheres on cam nothing dangles.
  std::vector<bool> all(m.links.size(), true);
  CHECK(listed_tool_frames(m, {"tcp"}, all) == Names{"tcp"});
  // The fingers without spheres: fl's child is listed (fr is a mimic, not actuated).
  const std::vector<bool> no_fingers{true, true, true, true, false, false, false, true};
  CHECK(listed_tool_frames(m, {"wrist"}, no_fingers) == Names{"wrist", "finger_l"});
}

TEST_CASE("the robot file keeps the planner setup and checks its names", "[planner]") {
  RobotModel m = gripper_arm();
  for (Link& l : m.links) l.spheres.outer.spheres = {{{0, 0, 0.05}, 0.04}};
  PlannerSetup s;
  s.tool_frames = {"wrist"};
  s.tool_frames_from = "gripper";
  s.locked_joints = {"fl"};
  s.default_positions = {{"j1", 0.25}, {"j2", 0.5}, {"fl", 0.0}, {"j3", -1.0 / 3}};
  s.default_from = "sample";
  SelfCollisionMatrix mx;
  mx.samples = 123;
  mx.seed = 7;
  mx.threshold = 0.9;
  mx.margin = 0.005;
  mx.srdf = "given.srdf";
  mx.pairs = {{"base", "upper", PairClass::kAdjacent, true, ""},
              {"base", "lower", PairClass::kSphereOnly, true, ""},
              {"base", "cam", PairClass::kGiven, true, "User said so"},
              {"upper", "cam", PairClass::kChecked, false, ""}};
  mx.buffer = {{"base", -0.002}, {"upper", 0.0}};
  s.self_collision = mx;
  m.planner = s;
  const RobotModel back = parse_robot(robot_to_json(m), "f");
  REQUIRE(back.planner);
  const PlannerSetup& b = *back.planner;
  CHECK(b.tool_frames == s.tool_frames);
  CHECK(b.tool_frames_from == "gripper");
  CHECK(b.locked_joints == s.locked_joints);
  CHECK(b.default_positions == s.default_positions);  // bit for bit
  CHECK(b.default_from == "sample");
  REQUIRE(b.self_collision);
  const SelfCollisionMatrix& c = *b.self_collision;
  CHECK(c.samples == 123);
  CHECK(c.seed == 7);
  CHECK(c.threshold == 0.9);
  CHECK(c.margin == 0.005);
  CHECK(c.srdf == "given.srdf");
  CHECK(c.buffer == mx.buffer);
  REQUIRE(c.pairs.size() == 4);
  for (std::size_t k = 0; k < 4; ++k) {
    CHECK(c.pairs[k].link1 == mx.pairs[k].link1);
    CHECK(c.pairs[k].link2 == mx.pairs[k].link2);
    CHECK(c.pairs[k].kind == mx.pairs[k].kind);
    CHECK(c.pairs[k].ignored == mx.pairs[k].ignored);
    CHECK(c.pairs[k].reason == mx.pairs[k].reason);
  }
  CHECK(ignored_pairs(c).size() == 3);

  // Every reference is checked, naming what is wrong.
  auto broken = [&](auto change) {
    RobotModel x = m;
    change(*x.planner);
    return x;
  };
  CHECK_THROWS_WITH(
      validate_robot_model(broken([](PlannerSetup& p) { p.tool_frames = {"ghost"}; }), "f"),
      Contains("f: planner: the tool frame \"ghost\""));
  CHECK_THROWS_WITH(
      validate_robot_model(broken([](PlannerSetup& p) { p.locked_joints = {"fr"}; }), "f"),
      Contains("\"fr\" is no actuated joint"));
  CHECK_THROWS_WITH(
      validate_robot_model(broken([](PlannerSetup& p) { p.default_positions.erase("j3"); }), "f"),
      Contains("joint \"j3\" has no default position"));
  CHECK_THROWS_WITH(
      validate_robot_model(
          broken([](PlannerSetup& p) { p.self_collision->pairs[1].link2 = "base"; }), "f"),
      Contains("names one link twice"));
  CHECK_THROWS_WITH(
      validate_robot_model(broken([](PlannerSetup& p) {
                             p.self_collision->pairs.push_back(p.self_collision->pairs[0]);
                           }),
                           "f"),
      Contains("is listed twice"));
  CHECK_THROWS_WITH(
      validate_robot_model(broken([](PlannerSetup& p) { p.self_collision->threshold = 2; }), "f"),
      Contains("not in [0, 1]"));
  CHECK_THROWS_WITH(
      parse_robot(robot_to_json(broken([](PlannerSetup&) {
                  })).replace(robot_to_json(m).find("\"sphere_only\""), 13, "\"sometimes\""),
                  "f"),
      Contains("class \"sometimes\" is unknown"));
  // The default setup: adjacency only, every actuated joint at the clamped zero.
  RobotModel d = m;
  d.planner.reset();
  const PlannerSetup def = planner_setup_or_default(d, std::vector<bool>(d.links.size(), true));
  CHECK(def.tool_frames == Names{"wrist", "cam"});
  CHECK(def.locked_joints == Names{"fl"});
  CHECK(def.default_from == "zero_unchecked");
  REQUIRE(def.self_collision);
  CHECK(def.self_collision->pairs.size() == 8 * 7 / 2);
  // The 5 moving joints' pairs, and the 3 pairs of the rigid body lower-wrist-tcp.
  CHECK(ignored_pairs(*def.self_collision).size() == 8);
}
