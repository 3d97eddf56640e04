// The robot checker (medspheres/check/robot_checker.h): a scene of obstacles, and verdicts
// for arrays of configurations and edges, the GIL released while it runs.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "medspheres/check/robot_checker.h"
#include "medspheres/robot_file.h"
#include "py_check_arrays.h"
#include "py_common.h"

namespace medspheres::python {

namespace {

check::Mode mode_of(const std::string& mode) {
  if (mode == "spheres") return check::Mode::spheres;
  if (mode == "bounds") return check::Mode::bounds;
  throw py::value_error("mode: expected 'spheres' or 'bounds', not '" + mode + "'");
}

std::vector<Eigen::Vector3d> points_of(const py::handle& array, const char* what) {
  const auto a = float_rows(array, 3, what);
  const auto r = a.unchecked<2>();
  std::vector<Eigen::Vector3d> out;
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out.emplace_back(r(i, 0), r(i, 1), r(i, 2));
  return out;
}

void register_scene(py::module_& m) {
  py::class_<check::Scene>(m, "CheckScene",
                           "Obstacles for a RobotChecker, in the world frame (metres): FCL's "
                           "primitives, meshes (surfaces), point clouds and octomap cells.")
      .def(py::init<>())
      .def(
          "add_sphere",
          [](check::Scene& s, const Eigen::Vector3d& c, double r, const std::string& name) {
            return s.add_sphere(c, r, name);
          },
          py::arg("center"), py::arg("radius"), py::arg("name") = "sphere")
      .def(
          "add_box",
          [](check::Scene& s, const Eigen::Vector3d& size, const py::handle& pose,
             const std::string& name) { return s.add_box(size, pose_of(pose, "pose"), name); },
          py::arg("size"), py::arg("pose") = py::none(), py::arg("name") = "box",
          "A box of the given side lengths centred on the 4 x 4 pose's origin.")
      .def(
          "add_capsule",
          [](check::Scene& s, double r, double length, const py::handle& pose,
             const std::string& name) {
            return s.add_capsule(r, length, pose_of(pose, "pose"), name);
          },
          py::arg("radius"), py::arg("length"), py::arg("pose") = py::none(),
          py::arg("name") = "capsule", "Along the pose's z axis, length of the axis segment.")
      .def(
          "add_cylinder",
          [](check::Scene& s, double r, double length, const py::handle& pose,
             const std::string& name) {
            return s.add_cylinder(r, length, pose_of(pose, "pose"), name);
          },
          py::arg("radius"), py::arg("length"), py::arg("pose") = py::none(),
          py::arg("name") = "cylinder")
      .def(
          "add_mesh",
          [](check::Scene& s, const py::handle& mesh, const py::handle& pose,
             const std::string& name) {
            return s.add_mesh(mesh_of_arrays(mesh), pose_of(pose, "pose"), name);
          },
          py::arg("mesh"), py::arg("pose") = py::none(), py::arg("name") = "mesh",
          "mesh: (vertices n x 3, triangles m x 3); a surface, as FCL's BVHModel.")
      .def(
          "add_points",
          [](check::Scene& s, const py::handle& p, const std::string& name) {
            return s.add_points(points_of(p, "points"), name);
          },
          py::arg("points"), py::arg("name") = "points")
      .def(
          "add_cells",
          [](check::Scene& s, const py::handle& c, double side, const std::string& name) {
            return s.add_cells(points_of(c, "centres"), side, name);
          },
          py::arg("centres"), py::arg("side"), py::arg("name") = "cells",
          "Axis-aligned cubes of one side (an octomap's occupied leaves).")
      .def("__len__", &check::Scene::size);
}

}  // namespace

void register_check(py::module_& m) {
  register_scene(m);
  register_certified(m);
  py::class_<check::RobotChecker, std::shared_ptr<check::RobotChecker>>(
      m, "RobotChecker",
      "Collision checks of a robot file's spheres for arrays of configurations and edges, "
      "four at a time in SIMD lanes; the GIL is released while they run. Verdicts: 0 free, "
      "1 colliding, 2 undecided (mode 'bounds' only).")
      .def(py::init([](const py::object& robot_file, const check::Scene& scene,
                       const py::object& fine, double margin,
                       const std::vector<std::pair<std::string, std::string>>& disabled,
                       bool self_collision, const py::handle& base_pose, const std::string& simd) {
             const RobotModel planner = load_robot(path_of(robot_file));
             std::unique_ptr<RobotModel> fine_model;
             if (!fine.is_none())
               fine_model = std::make_unique<RobotModel>(load_robot(path_of(fine)));
             check::CheckerOptions o;
             o.margin = margin;
             o.disabled = disabled;
             o.self = self_collision;
             o.X_WB = pose_of(base_pose, "base_pose");
             o.simd = simd_of(simd);
             py::gil_scoped_release release;
             return std::make_shared<check::RobotChecker>(planner, scene, o, fine_model.get());
           }),
           py::arg("robot_file"), py::arg("scene") = check::Scene(), py::kw_only(),
           py::arg("fine") = py::none(), py::arg("margin") = 0.0,
           py::arg("disabled") = std::vector<std::pair<std::string, std::string>>{},
           py::arg("self_collision") = true, py::arg("base_pose") = py::none(),
           py::arg("simd") = "auto",
           "From a robot file (the planner's spheres) and a CheckScene; fine: a robot file of "
           "the same robot with larger sets, checked after the planner's in mode 'bounds'.")
      .def_property_readonly("joint_names", &check::RobotChecker::joint_names)
      .def_property_readonly("links", &check::RobotChecker::links)
      .def_property_readonly("uses_avx2", &check::RobotChecker::uses_avx2)
      .def_property_readonly("allowance", &check::RobotChecker::allowance)
      .def(
          "check",
          [](const check::RobotChecker& c, const py::handle& q, const std::string& mode,
             int threads) {
            const auto a = configurations(q, c.num_positions(), "q");
            std::vector<check::Verdict> out(static_cast<std::size_t>(a.shape(0)));
            const check::Mode chosen = mode_of(mode);
            {
              py::gil_scoped_release release;
              c.check(a.data(), out.size(), chosen, out.data(), threads);
            }
            return verdict_array(out);
          },
          py::arg("q"), py::arg("mode") = "spheres", py::arg("threads") = 1,
          "Verdicts (uint8 array of n) of the n x dof configurations q; threads 0: every core.")
      .def(
          "with_scene",
          [](const check::RobotChecker& c, const check::Scene& scene) {
            py::gil_scoped_release release;
            return c.with_scene(scene);
          },
          py::arg("scene"),
          "The same robot and options against another CheckScene, the self pairs' tables "
          "shared (a planner's next problem): the verdicts of a checker built anew.")
      .def(
          "any_colliding",
          [](const check::RobotChecker& c, const py::handle& q) {
            const auto a = configurations(q, c.num_positions(), "q");
            py::gil_scoped_release release;
            return c.any_colliding(a.data(), static_cast<std::size_t>(a.shape(0)));
          },
          py::arg("q"),
          "Whether some of the n x dof configurations q collides (mode 'spheres'), eight at a "
          "time, stopping at the first found: a planner's own motion validation.")
      .def(
          "check_edges",
          [](const check::RobotChecker& c, const py::handle& q0, const py::handle& q1,
             double resolution, const std::string& mode, int threads) {
            const auto a = configurations(q0, c.num_positions(), "q0");
            const auto b = configurations(q1, c.num_positions(), "q1");
            if (a.shape(0) != b.shape(0)) throw py::value_error("q0 and q1: not as many rows");
            std::vector<check::Verdict> out(static_cast<std::size_t>(a.shape(0)));
            const check::Mode chosen = mode_of(mode);
            std::size_t checked = 0;
            {
              py::gil_scoped_release release;
              checked = c.check_edges(a.data(), b.data(), out.size(), resolution, chosen,
                                      out.data(), threads);
            }
            return py::make_tuple(verdict_array(out), checked);
          },
          py::arg("q0"), py::arg("q1"), py::arg("resolution"), py::arg("mode") = "spheres",
          py::arg("threads") = 1,
          "(verdicts, configurations checked) of the edges q0[i] -> q1[i], sampled at "
          "t = k / n, n = ceil(|q1 - q0| / resolution), in rake order.");
}

}  // namespace medspheres::python
