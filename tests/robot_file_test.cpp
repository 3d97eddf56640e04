#include <cstring>
#include <random>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/robot_file.h"
#include "support/robot_fixtures.h"
#include "support/temp_dir.h"

using Catch::Matchers::Contains;
using medspheres::InputError;
using medspheres::RobotModel;
using medspheres::test::TempDir;
using medspheres::test::three_link_arm;

namespace {

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

medspheres::SphereSet random_spheres(std::size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-2.0, 2.0), r(1e-6, 0.3);
  medspheres::SphereSet s;
  for (std::size_t i = 0; i < n; ++i) s.spheres.push_back({{u(rng), u(rng), u(rng)}, r(rng)});
  return s;
}

RobotModel decorated_arm() {
  RobotModel m = three_link_arm();
  std::mt19937_64 rng(11);
  for (auto& l : m.links) {
    l.spheres.inner = random_spheres(7, rng);
    l.spheres.outer = random_spheres(5, rng);
  }
  m.links[1].spheres.outer_certificate_json = R"({"kind":"triangle corners","gap":0.001})";
  m.links[4].spheres = {};
  m.links[4].note = "no collision geometry";
  // A rotation with no special structure.
  m.joints[0].origin.linear() =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  m.joints[0].origin.translation() = Eigen::Vector3d(0.1, 1.0 / 3.0, 1e-17);
  m.joints[1].axis = Eigen::Vector3d(1, 1, 0).normalized();
  m.metadata_json = R"({"urdf":"arm.urdf","meshes":{"a.stl":"abc"},"x":[1,2.5,null]})";
  return m;
}

std::string load_problem(const TempDir& dir, const std::string& text) {
  const std::string path = dir.write("bad.robot.json", text);
  try {
    medspheres::load_robot(path);
  } catch (const InputError& e) {
    CHECK(e.source() == path);
    return e.problem();
  }
  return "";
}

}  // namespace

TEST_CASE("robot files round-trip: spheres, joints and metadata bit-exact", "[robot_file]") {
  TempDir dir;
  const RobotModel m = decorated_arm();
  const std::string path = dir.file("arm.robot.json");
  medspheres::save_robot(m, path);
  const RobotModel t = medspheres::load_robot(path);
  CHECK(t.name == m.name);
  CHECK(t.root_link == m.root_link);
  CHECK(t.metadata_json == m.metadata_json);
  REQUIRE(t.links.size() == m.links.size());
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const auto &a = m.links[i], &b = t.links[i];
    CHECK(a.name == b.name);
    CHECK(a.note == b.note);
    CHECK(a.spheres.outer_certificate_json == b.spheres.outer_certificate_json);
    for (auto [x, y] : {std::pair{&a.spheres.inner, &b.spheres.inner},
                        std::pair{&a.spheres.outer, &b.spheres.outer}}) {
      REQUIRE(x->size() == y->size());
      for (std::size_t k = 0; k < x->size(); ++k) {
        CHECK(same_bits(x->spheres[k].radius, y->spheres[k].radius));
        for (int c = 0; c < 3; ++c)
          CHECK(same_bits(x->spheres[k].center[c], y->spheres[k].center[c]));
      }
    }
  }
  REQUIRE(t.joints.size() == m.joints.size());
  for (std::size_t i = 0; i < m.joints.size(); ++i) {
    const auto &a = m.joints[i], &b = t.joints[i];
    CHECK((a.name == b.name && a.type == b.type && a.parent == b.parent && a.child == b.child));
    CHECK(a.origin.translation() == b.origin.translation());  // exact
    CHECK(a.axis == b.axis);
    // The rotation travels as a quaternion: its matrix agrees to rounding.
    CHECK((a.origin.linear() - b.origin.linear()).cwiseAbs().maxCoeff() < 4e-16);
    CHECK(a.limits.has_value() == b.limits.has_value());
    if (a.limits)
      CHECK((a.limits->lower == b.limits->lower && a.limits->upper == b.limits->upper &&
             a.limits->velocity == b.limits->velocity && a.limits->effort == b.limits->effort));
    CHECK(a.mimic.has_value() == b.mimic.has_value());
    if (a.mimic)
      CHECK((a.mimic->joint == b.mimic->joint && a.mimic->multiplier == b.mimic->multiplier &&
             a.mimic->offset == b.mimic->offset));
  }
}

TEST_CASE("a robot file's metadata replaced in its text: the bytes robot_to_json writes",
          "[robot_file]") {
  RobotModel m = decorated_arm();
  const std::string text = medspheres::robot_to_json(m);
  CHECK(nlohmann::json::parse(medspheres::robot_json_metadata(text, "arm")) ==
        nlohmann::json::parse(m.metadata_json));
  m.metadata_json = R"({"urdf":"elsewhere/arm.urdf","n":[0.1,-0.0,1e-300,3]})";
  CHECK(medspheres::robot_json_with_metadata(text, m.metadata_json, "arm") ==
        medspheres::robot_to_json(m));
  CHECK_THROWS_AS(medspheres::robot_json_with_metadata("[1]", "{}", "arm"), InputError);
  CHECK_THROWS_AS(medspheres::robot_json_with_metadata(text, "[]", "arm"), std::invalid_argument);
}

TEST_CASE("a robot file accepts rpy origins as URDF defines them", "[robot_file]") {
  const RobotModel m = medspheres::parse_robot(R"({
    "format": "medspheres.robot", "version": 1, "name": "r", "root_link": "a",
    "links": [{"name": "a"}, {"name": "b"}],
    "joints": [{"name": "j", "type": "fixed", "parent": "a", "child": "b",
                "origin": {"xyz": [1, 2, 3], "rpy": [0.1, 0.2, 0.3]}}]})",
                                               "inline");
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  CHECK((m.joints[0].origin.linear() - R).cwiseAbs().maxCoeff() < 1e-15);
  CHECK(m.joints[0].origin.translation() == Eigen::Vector3d(1, 2, 3));
}

TEST_CASE("malformed robot files name the file, the link or joint and the problem",
          "[robot_file]") {
  TempDir dir;
  const std::string head = R"("format": "medspheres.robot", "version": 1, "root_link": "a", )";
  CHECK_THAT(load_problem(dir, "{"), Contains("not valid JSON"));
  CHECK_THAT(load_problem(dir, R"({"format": "x", "version": 1})"), Contains("\"format\""));
  CHECK_THAT(load_problem(dir, R"({"format": "medspheres.robot", "version": 9})"),
             Contains("version 9"));
  CHECK_THAT(load_problem(dir, "{" + head + R"("links": [{"name": "a", "inner": [[0, 0, 0]]}],
             "joints": []})"),
             Contains("link \"a\"") && Contains("[x, y, z, r]"));
  CHECK_THAT(load_problem(dir, "{" + head + R"("links": [{"name": "a", "outer": [[0, 0, 0, -1]]}],
             "joints": []})"),
             Contains("link \"a\" outer set") && Contains("radius"));
  CHECK_THAT(load_problem(dir, "{" + head + R"("links": [{"name": "a"}, {"name": "b"}],
             "joints": [{"name": "j", "type": "ball", "parent": "a", "child": "b"}]})"),
             Contains("joint \"j\"") && Contains("ball"));
  CHECK_THAT(load_problem(dir, "{" + head + R"("links": [{"name": "a"}, {"name": "b"}],
             "joints": [{"name": "j", "type": "revolute", "parent": "a", "child": "b",
                         "axis": [0, "x", 1]}]})"),
             Contains("joint \"j\"") && Contains("axis"));
  CHECK_THAT(load_problem(dir, "{" + head + R"("links": [{"name": "a"}, {"name": "b"}],
             "joints": [{"name": "j", "type": "revolute", "parent": "a", "child": "b",
                         "origin": {"quaternion_xyzw": [0, 0, 0, 2]}}]})"),
             Contains("joint \"j\" origin") && Contains("unit quaternion"));
  CHECK_THAT(load_problem(dir, "{" + head + R"("links": [{"name": "a"}, {"name": "b"}],
             "joints": [{"name": "j", "type": "revolute", "parent": "a", "child": "b",
                         "mimic": {"joint": "k"}}]})"),
             Contains("joint \"j\" mimics the joint \"k\""));
  CHECK_THAT(load_problem(dir, "{" + head + R"("links": [{"name": "a"}], "joints": {}})"),
             Contains("\"joints\" is not a list"));
}
