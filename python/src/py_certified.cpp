// CertifiedChecker (fcl_adapter's certified_checker.h): the robot checker's bounds mode with
// the exact meshes of the robot's URDF as its fallback, for arrays of configurations and
// edges; every verdict certified, the GIL released while it runs.
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "medspheres/fcl/certified_checker.h"
#include "medspheres/fcl/fcl_from_scene.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_file.h"
#include "py_check_arrays.h"

namespace medspheres::python {

namespace {

using Meshes = std::map<std::string, std::shared_ptr<const fcl::MeshModel>>;

// The checker with what it points at: the scene's FCL objects (the fallback holds their
// addresses) and the models.
struct Certified {
  fcl::FclObjects scene;
  std::vector<std::unique_ptr<const RobotModel>> models;
  std::unique_ptr<const fcl::CertifiedChecker> checker;
};

struct Inputs {
  std::string urdf, planner, fine, trees;  // fine, trees: empty for none
  std::map<std::string, std::string> packages;
  check::CheckerOptions options;
  fcl::FallbackOptions fallback;
};

// The URDF's exact link meshes (every link with a meshed part), in the link frames.
Meshes link_meshes(const UrdfRobot& robot) {
  Meshes out;
  for (const LinkSolid& s : load_link_solids(robot))
    if (!s.parts.empty()) out[s.link] = fcl::make_mesh_model(s.placed_mesh());
  return out;
}

// The robot file \p path, checked to hold the URDF's links; null for an empty path.
const RobotModel* model_of(Certified& c, const std::string& path, const UrdfRobot& robot) {
  if (path.empty()) return nullptr;
  auto m = std::make_unique<const RobotModel>(load_robot(path));
  require_same_links(*m, robot, path);
  c.models.push_back(std::move(m));
  return c.models.back().get();
}

std::shared_ptr<Certified> make_certified(Inputs in, const check::Scene& scene) {
  auto c = std::make_shared<Certified>();
  c->scene = fcl::fcl_from_scene(scene);
  UrdfReadOptions read;
  for (const auto& [package, dir] : in.packages)
    add_package_dir(read.packages, package + "=" + dir);
  const UrdfRobot robot = read_urdf(in.urdf, read);
  const RobotModel* planner = model_of(*c, in.planner, robot);
  const RobotModel* fine = model_of(*c, in.fine, robot);
  in.fallback.trees = model_of(*c, in.trees, robot);
  c->checker = std::make_unique<const fcl::CertifiedChecker>(
      *planner, fine, link_meshes(robot), c->scene.objects, in.options, in.fallback);
  return c;
}

// The same robot and fallback against another scene (CertifiedChecker::with_scene).
std::shared_ptr<Certified> with_scene(const Certified& c, const check::Scene& scene) {
  auto out = std::make_shared<Certified>();
  out->scene = fcl::fcl_from_scene(scene);
  out->checker =
      std::make_unique<const fcl::CertifiedChecker>(c.checker->with_scene(out->scene.objects));
  return out;
}

py::dict stats_dict(const fcl::FallbackStats& s) {
  py::dict d;
  d["table_first"] = s.table_first;
  d["configurations"] = s.configurations;
  d["witnessed"] = s.witnessed;
  d["tabled"] = s.tabled;
  d["pairs"] = s.pairs;
  d["planes"] = s.planes;
  d["meshes"] = s.meshes;
  return d;
}

std::string optional_path(const py::object& path) {
  return path.is_none() ? "" : path_of(path);
}

py::object check_rows(const Certified& c, const py::handle& q, int threads, bool with_stats) {
  const check::RobotChecker& k = c.checker->spheres();
  const auto a = configurations(q, k.num_positions(), "q");
  std::vector<check::Verdict> out(static_cast<std::size_t>(a.shape(0)));
  fcl::FallbackStats stats;
  {
    py::gil_scoped_release release;
    c.checker->check(a.data(), out.size(), out.data(), threads, &stats);
  }
  if (!with_stats) return verdict_array(out);
  return py::make_tuple(verdict_array(out), stats_dict(stats));
}

py::tuple check_edges(const Certified& c, const py::handle& q0, const py::handle& q1,
                      double resolution, int threads) {
  const std::size_t dof = c.checker->spheres().num_positions();
  const auto a = configurations(q0, dof, "q0");
  const auto b = configurations(q1, dof, "q1");
  if (a.shape(0) != b.shape(0)) throw py::value_error("q0 and q1: not as many rows");
  std::vector<check::Verdict> out(static_cast<std::size_t>(a.shape(0)));
  std::size_t checked = 0;
  {
    py::gil_scoped_release release;
    checked =
        c.checker->check_edges(a.data(), b.data(), out.size(), resolution, out.data(), threads);
  }
  return py::make_tuple(verdict_array(out), checked);
}

}  // namespace

void register_certified(py::module_& m) {
  py::class_<Certified, std::shared_ptr<Certified>>(
      m, "CertifiedChecker",
      "Certified collision checks of a robot for arrays of configurations and edges: the "
      "robot file's spheres first (RobotChecker's bounds mode), then, for the pairs they "
      "leave undecided, the exact meshes of its URDF. Verdicts: 0 free, 1 colliding, each "
      "certified (never a missed collision); 2 undecided only for a pair with no mesh. "
      "Immutable; the GIL is released while it runs, so threads may share it.")
      .def(py::init([](const py::object& urdf, const py::object& robot_file,
                       const check::Scene& scene, const py::object& fine, const py::object& trees,
                       const std::map<std::string, std::string>& packages, double margin,
                       const std::vector<std::pair<std::string, std::string>>& disabled,
                       bool self_collision, const py::handle& base_pose, const std::string& simd,
                       std::size_t order_samples, unsigned seed, std::size_t table_cells,
                       std::size_t table_pairs, const std::string& table_store) {
             Inputs in;
             in.urdf = path_of(urdf);
             in.planner = path_of(robot_file);
             in.fine = optional_path(fine);
             in.trees = optional_path(trees);
             in.packages = packages;
             in.options.margin = margin;
             in.options.disabled = disabled;
             in.options.self = self_collision;
             in.options.X_WB = pose_of(base_pose, "base_pose");
             in.options.simd = simd_of(simd);
             in.fallback.order.samples = order_samples;
             in.fallback.order.margin = margin;
             in.fallback.order.seed = seed;
             in.fallback.table_cells = table_cells;
             in.fallback.table_pairs = table_pairs;
             in.fallback.table_store = table_store;
             py::gil_scoped_release release;
             return make_certified(std::move(in), scene);
           }),
           py::arg("urdf"), py::arg("robot_file"), py::arg("scene") = check::Scene(), py::kw_only(),
           py::arg("fine") = py::none(), py::arg("trees") = py::none(),
           py::arg("packages") = std::map<std::string, std::string>{}, py::arg("margin") = 0.0,
           py::arg("disabled") = std::vector<std::pair<std::string, std::string>>{},
           py::arg("self_collision") = true, py::arg("base_pose") = py::none(),
           py::arg("simd") = "auto", py::arg("order_samples") = 0, py::arg("seed") = 1,
           py::arg("table_cells") = 0, py::arg("table_pairs") = 0, py::arg("table_store") = "",
           "urdf: the robot (its link meshes are the fallback; packages: {'pkg': '/dir'} for "
           "package:// URIs); robot_file: its planner spheres (.robot.json with certified "
           "covers, as bake_robot writes it); scene: a CheckScene (no point clouds: give "
           "them as cells). fine, trees: robot files of the same robot with larger sets, the "
           "level after the planner's and the fallback's sphere trees. order_samples > 0: "
           "that many seeded configurations order the fallback's self pairs and learn witness "
           "pairs. table_cells > 0: joint-space tables of the self pairs (at most table_pairs "
           "of them when > 0), kept in the folder table_store when given.")
      .def_property_readonly("joint_names",
                             [](const Certified& c) { return c.checker->spheres().joint_names(); })
      .def_property_readonly("links",
                             [](const Certified& c) { return c.checker->spheres().links(); })
      .def(
          "with_scene",
          [](const Certified& c, const check::Scene& scene) {
            py::gil_scoped_release release;
            return with_scene(c, scene);
          },
          py::arg("scene"),
          "The same robot and fallback against another CheckScene (a planner's next "
          "problem): the fallback's geometries, learnt witnesses and joint-space tables are "
          "shared, only the scene's parts are built; the verdicts of a checker built anew.")
      .def("check", &check_rows, py::arg("q"), py::arg("threads") = 1, py::arg("stats") = false,
           "Verdicts (uint8 array of n) of the n x dof configurations q; threads 0: every "
           "core. stats: (verdicts, {what the fallback did: 'configurations' that reached it, "
           "'pairs' its sphere trees decided, 'meshes' the exact meshes settled, ...}).")
      .def("check_edges", &check_edges, py::arg("q0"), py::arg("q1"), py::arg("resolution"),
           py::arg("threads") = 1,
           "(verdicts, configurations checked) of the edges q0[i] -> q1[i], sampled as "
           "RobotChecker.check_edges samples them, every sample certified.");
}

}  // namespace medspheres::python
