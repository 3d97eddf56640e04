// RobotBounds: certified distance bounds and three-valued collision of a whole robot
// (fcl_adapter's robot_bounds.h) against itself and a scene of posed sphere sets.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <fcl/geometry/shape/sphere.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/robot_file.h"
#include "py_common.h"

namespace medspheres::python {

namespace {

// The scene [(balls, pose), ...] as FCL objects, one fcl::Sphere primitive per ball (exact
// on both sides of the bounds; the objects own their geometries).
struct Scene {
  std::vector<std::unique_ptr<::fcl::CollisionObjectd>> objects;
  std::vector<const ::fcl::CollisionObjectd*> pointers;
};

Scene scene_of(const py::handle& scene) {
  Scene out;
  for (const py::handle item : scene) {
    const py::tuple pair = py::tuple(py::reinterpret_borrow<py::object>(item));
    if (pair.size() != 2) throw py::value_error("scene: expected (spheres, pose) pairs");
    const SphereSet balls = sphere_set_of(pair[0], "scene spheres");
    validate_sphere_set(balls, "scene spheres");
    const Eigen::Isometry3d X = pose_of(pair[1], "scene pose");
    for (const Sphere& b : balls.spheres) {
      auto g = std::make_shared<::fcl::Sphered>(b.radius);
      ::fcl::Transform3d at = ::fcl::Transform3d::Identity();
      at.translation() = X * b.center;
      out.objects.push_back(std::make_unique<::fcl::CollisionObjectd>(g, at));
      out.pointers.push_back(out.objects.back().get());
    }
  }
  return out;
}

}  // namespace

void register_robot_bounds(py::module_& m) {
  py::class_<fcl::RobotBounds, std::shared_ptr<fcl::RobotBounds>>(
      m, "RobotBounds",
      "A robot file's links as inner and certified outer sets, posed by forward kinematics: "
      "certified bounds on its distance to a scene and to itself (adjacent links and the "
      "`disabled` pairs left out). Immutable; queries release the GIL.")
      .def(py::init([](const py::object& robot_file,
                       const std::vector<std::pair<std::string, std::string>>& disabled,
                       bool allow_uncertified, std::size_t order_samples, double order_margin,
                       unsigned seed) {
             const RobotModel model = load_robot(path_of(robot_file));
             fcl::BoundedGeometryOptions o;
             o.allow_uncertified = allow_uncertified;
             fcl::SelfPairOrder order;
             order.samples = order_samples;
             order.margin = order_margin;
             order.seed = seed;
             return std::make_shared<fcl::RobotBounds>(
                 model, std::map<std::string, std::shared_ptr<const fcl::MeshModel>>{}, disabled, o,
                 order);
           }),
           py::arg("robot_file"),
           py::arg("disabled") = std::vector<std::pair<std::string, std::string>>{},
           py::arg("allow_uncertified") = false, py::arg("order_samples") = 0,
           py::arg("order_margin") = 0.0, py::arg("seed") = 1,
           "From a medspheres robot file (.robot.json, as bake_robot writes it). With "
           "order_samples > 0, that many seeded configurations order the self pairs and pick "
           "witness sphere pairs at order_margin (SelfPairOrder): collide() is then faster "
           "on robots that often collide with themselves, with the same verdicts.")
      .def_property_readonly(
          "witnesses", [](const fcl::RobotBounds& r) { return r.witnesses().size(); },
          "How many witness sphere pairs the order's samples picked.")
      .def_property_readonly("joint_names",
                             [](const fcl::RobotBounds& r) { return r.kinematics().joint_names(); })
      .def(
          "bounds",
          [](const fcl::RobotBounds& r, const Eigen::VectorXd& q, const py::object& scene,
             bool include_self, const py::handle& base_pose) {
            const Scene s = scene_of(scene);
            const Eigen::Isometry3d X_WB = pose_of(base_pose, "base_pose");
            fcl::RobotBoundsResult b;
            {
              py::gil_scoped_release release;
              b = fcl::robot_bounds(r, q, s.pointers, include_self, false, X_WB);
            }
            return py::make_tuple(b.minimum.lower, b.minimum.upper, b.certified);
          },
          py::arg("q"), py::arg("scene") = py::list(), py::arg("include_self") = true,
          py::arg("base_pose") = py::none(),
          "(lower, upper, certified) on the smallest distance at joint positions q (in "
          "joint_names order) to the scene [(balls n x 4, 4 x 4 pose), ...] (each ball an "
          "exact FCL sphere) and, with include_self, between the robot's own links.")
      .def(
          "collide",
          [](const fcl::RobotBounds& r, const Eigen::VectorXd& q, const py::object& scene,
             bool include_self, double margin, const py::handle& base_pose) {
            const Scene s = scene_of(scene);
            const Eigen::Isometry3d X_WB = pose_of(base_pose, "base_pose");
            fcl::RobotCollideResult c;
            {
              py::gil_scoped_release release;
              c = fcl::robot_collide(r, q, s.pointers, include_self, margin, X_WB);
            }
            py::dict out;
            out["verdict"] = verdict_text(c.verdict);
            out["pairs_tested"] = c.pairs_tested;
            out["by_witness"] = c.by_witness;
            out["certified"] = c.certified;
            return out;
          },
          py::arg("q"), py::arg("scene") = py::list(), py::arg("include_self") = true,
          py::arg("margin") = 0.0, py::arg("base_pose") = py::none(),
          "Three-valued collision within margin: {'verdict': 'free' | 'colliding' | "
          "'undecided', 'pairs_tested', 'by_witness', 'certified'}.");
}

}  // namespace medspheres::python
