// Queries on posed sphere sets: SphereTree (distance, collision, points) and
// BoundedGeometry (certified distance bounds, three-valued collision).
#include <cstdint>
#include <memory>
#include <string>

#include <pybind11/stl.h>

#include "medspheres/error.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/point_distances.h"
#include "medspheres/sphere_tree.h"
#include "py_common.h"

namespace medspheres::python {

namespace {

SphereTreeOptions tree_options(const std::string& kind, int max_leaf_size) {
  SphereTreeOptions o;
  if (kind == "rss")
    o.kind = BoundingVolumeKind::rss;
  else if (kind == "ball")
    o.kind = BoundingVolumeKind::ball;
  else
    throw InputError::option(ErrorKind::kOutOfRange, "kind", kind,
                             "must be rss or ball, got '" + kind + "'");
  o.max_leaf_size = max_leaf_size;
  return o;
}

py::tuple point3(const Eigen::Vector3d& p) {
  return py::make_tuple(p.x(), p.y(), p.z());
}

py::dict distance_dict(const TreeDistance& d) {
  py::dict out;
  out["distance"] = d.distance;
  out["point_a"] = point3(d.p_WPa);
  out["point_b"] = point3(d.p_WPb);
  out["sphere_a"] = d.sphere_a;
  out["sphere_b"] = d.primitive_b;
  return out;
}

py::object point_distance_py(const SphereTree& tree, const py::handle& points,
                             const py::handle& pose, bool return_index) {
  auto p = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
  if (!p || p.ndim() != 2 || p.shape(1) != 3)
    throw py::value_error("points: expected an n x 3 array of numbers");
  const Eigen::Isometry3d X = pose_of(pose, "pose");
  const auto n = p.shape(0);
  py::array_t<double> out(n);
  py::array_t<std::intptr_t> index(return_index ? n : 0);
  double* o = out.mutable_data();
  std::intptr_t* idx = return_index ? index.mutable_data() : nullptr;
  const double* xyz = p.data();
  {
    py::gil_scoped_release release;
    point_distances(tree, X, xyz, static_cast<std::size_t>(n), o, idx);
  }
  if (return_index) return py::make_tuple(out, index);
  return std::move(out);
}

void register_tree(py::module_& m) {
  py::class_<SphereTree, std::shared_ptr<SphereTree>>(
      m, "SphereTree",
      "A bounding-volume hierarchy over a sphere set, for distance and collision queries. "
      "Immutable: any number of threads may query it at once (the GIL is released).")
      .def(py::init([](const py::handle& spheres, const std::string& kind, int max_leaf_size) {
             return std::make_shared<SphereTree>(sphere_set_of(spheres, "spheres"),
                                                 tree_options(kind, max_leaf_size));
           }),
           py::arg("spheres"), py::arg("kind") = "rss", py::arg("max_leaf_size") = 8,
           "From a SphereSet or an n x 4 array; `kind` 'rss' or 'ball' nodes.")
      .def("__len__", &SphereTree::num_spheres)
      .def(
          "distance",
          [](const SphereTree& a, const SphereTree& b, const py::handle& pose,
             const py::handle& other_pose, bool signed_) {
            const Eigen::Isometry3d X_WA = pose_of(pose, "pose");
            const Eigen::Isometry3d X_WB = pose_of(other_pose, "other_pose");
            TreeDistance d;
            {
              py::gil_scoped_release release;
              d = signed_ ? signed_distance(a, X_WA, b, X_WB) : distance(a, X_WA, b, X_WB);
            }
            return distance_dict(d);
          },
          py::arg("other"), py::arg("pose") = py::none(), py::arg("other_pose") = py::none(),
          py::arg("signed") = false,
          "Distance between the unions of two posed sets (4 x 4 poses in the world, None: "
          "identity): {'distance', 'point_a', 'point_b' (world), 'sphere_a', 'sphere_b'}. "
          "Overlapping sets give a value <= 0: with signed=True minus the deepest pair's "
          "penetration, else the first overlapping pair found.")
      .def(
          "collide",
          [](const SphereTree& a, const SphereTree& b, const py::handle& pose,
             const py::handle& other_pose) {
            const Eigen::Isometry3d X_WA = pose_of(pose, "pose");
            const Eigen::Isometry3d X_WB = pose_of(other_pose, "other_pose");
            py::gil_scoped_release release;
            return collide(a, X_WA, b, X_WB);
          },
          py::arg("other"), py::arg("pose") = py::none(), py::arg("other_pose") = py::none(),
          "Whether any two balls touch or overlap.")
      .def("point_distance", &point_distance_py, py::arg("points"), py::arg("pose") = py::none(),
           py::arg("return_index") = false,
           "Signed distance from each point (n x 3, world) to the union of the posed balls: "
           "an n float64 array (with return_index, also the n intp indices of the realising "
           "balls). Inside a ball it is minus the depth in the deepest ball.");
}

void register_bounded(py::module_& m) {
  py::class_<fcl::BoundedGeometry, std::shared_ptr<fcl::BoundedGeometry>>(
      m, "BoundedGeometry",
      "A solid held by an inner set (inside it) and an outer covering set (its union "
      "contains the surface, certified), for certified distance bounds.")
      .def(py::init([](const py::handle& inner, const py::handle& outer, const std::string& name,
                       bool allow_uncertified) {
             fcl::BoundedGeometryOptions o;
             o.allow_uncertified = allow_uncertified;
             return std::make_shared<fcl::BoundedGeometry>(
                 name, sphere_set_of(inner, "inner"), sphere_set_of(outer, "outer"), nullptr, o);
           }),
           py::arg("inner"), py::arg("outer"), py::arg("name") = "object",
           py::arg("allow_uncertified") = false,
           "`outer` must be a SphereSet whose metadata records a certified cover (a "
           "bake(method='cover') result) unless allow_uncertified.")
      .def_property_readonly("certified", &fcl::BoundedGeometry::certified);
  m.def(
      "distance_bounds",
      [](const fcl::BoundedGeometry& a, const fcl::BoundedGeometry& b, const py::handle& pose_a,
         const py::handle& pose_b) {
        const Eigen::Isometry3d X_WA = pose_of(pose_a, "pose_a");
        const Eigen::Isometry3d X_WB = pose_of(pose_b, "pose_b");
        fcl::BoundsResult r;
        {
          py::gil_scoped_release release;
          r = fcl::distance_bounds(a, X_WA, b, X_WB);
        }
        return py::make_tuple(r.bounds.lower, r.bounds.upper, r.certified);
      },
      py::arg("a"), py::arg("b"), py::arg("pose_a") = py::none(), py::arg("pose_b") = py::none(),
      "(lower, upper, certified): lower <= d(A, B) <= upper for the posed solids.");
  m.def(
      "collide_bounds",
      [](const fcl::BoundedGeometry& a, const fcl::BoundedGeometry& b, const py::handle& pose_a,
         const py::handle& pose_b, double margin) {
        const Eigen::Isometry3d X_WA = pose_of(pose_a, "pose_a");
        const Eigen::Isometry3d X_WB = pose_of(pose_b, "pose_b");
        fcl::CollideResult r;
        {
          py::gil_scoped_release release;
          r = fcl::collide(a, X_WA, b, X_WB, margin);
        }
        py::dict out;
        out["verdict"] = verdict_text(r.verdict);
        out["lower"] = r.bounds.lower;
        out["upper"] = r.bounds.upper;
        out["certified"] = r.certified;
        return out;
      },
      py::arg("a"), py::arg("b"), py::arg("pose_a") = py::none(), py::arg("pose_b") = py::none(),
      py::arg("margin") = 0.0,
      "Three-valued collision within `margin`: {'verdict': 'free' | 'colliding' | "
      "'undecided', 'lower', 'upper', 'certified'} (bounds only as tight as the verdict "
      "needed).");
}

}  // namespace

const char* verdict_text(BoundsVerdict v) {
  switch (v) {
    case BoundsVerdict::free:
      return "free";
    case BoundsVerdict::colliding:
      return "colliding";
    case BoundsVerdict::undecided:
      break;
  }
  return "undecided";
}

void register_queries(py::module_& m) {
  register_tree(m);
  register_bounded(m);
  register_robot_bounds(m);
}

}  // namespace medspheres::python
