#pragma once
// Conversions the bindings share: numpy arrays to and from the library's types, poses,
// JSON text to Python objects. No medspheres logic lives here.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Geometry>

#include "medspheres/measure/fit_metrics.h"
#include "medspheres/sphere_set.h"
#include "medspheres/sphere_tree.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres::python {

namespace py = pybind11;

void register_errors(py::module_& m);
void register_sphere_set(py::module_& m);
void register_bake(py::module_& m);
void register_robot(py::module_& m);
void register_queries(py::module_& m);
void register_robot_bounds(py::module_& m);
void register_check(py::module_& m);

/// \p a as an n x \p columns float64 C-contiguous array; ValueError naming \p what otherwise.
py::array_t<double, py::array::c_style | py::array::forcecast> float_rows(const py::handle& a,
                                                                          py::ssize_t columns,
                                                                          const std::string& what);

/// An n x 4 float64 array (x, y, z, r) as balls; ValueError naming \p what for another shape.
SphereSet sphere_set_of_array(const py::handle& array, const std::string& what);

/// A SphereSet, or an n x 4 array, as a SphereSet (copied).
SphereSet sphere_set_of(const py::handle& object, const std::string& what);

/// n x 4 float64 copy of \p spheres.
py::array_t<double> spheres_array(const std::vector<Sphere>& spheres);

/// (V, F): V n x 3 float, F m x 3 integer, as a TriangleMesh. ValueError for other shapes
/// or indices out of int's range (indices into V are checked by the library).
TriangleMesh mesh_of_arrays(const py::handle& pair);

/// A 4 x 4 homogeneous rigid transform (None: identity) as an isometry; ValueError
/// naming \p what for another shape, a last row other than (0, 0, 0, 1), or non-finite
/// entries.
Eigen::Isometry3d pose_of(const py::handle& pose, const char* what);

/// "free", "colliding" or "undecided".
const char* verdict_text(BoundsVerdict verdict);

/// A length keyword \p field as the library's text (parse_length): None as nullopt, a str as
/// given, a real number (not a bool) as its shortest round-trip text.
/// \throws InputError (kOutOfRange, field \p field) for any other type.
std::optional<std::string> length_text(const py::handle& value, const char* field);

/// A mapping link name -> spheres (a SphereSet or an n x 4 array) as sets; \p what names it
/// in errors.
std::map<std::string, SphereSet> link_spheres_of(const py::handle& mapping,
                                                 const std::string& what);

/// Defines \p name(\p first, spheres, *, samples, surface_samples, seed, threads, ...): the
/// evaluation options as keywords with the library's defaults (FitOptions), then \p extra
/// (more keywords, the docstring). \p f takes its parameters in that order.
template <class F, class... Extra>
void def_evaluation(py::module_& m, const char* name, F&& f, const char* first, Extra&&... extra) {
  const FitOptions d;
  m.def(name, std::forward<F>(f), py::arg(first), py::arg("spheres"), py::kw_only(),
        py::arg("samples") = static_cast<long long>(d.volume_samples),
        py::arg("surface_samples") = static_cast<long long>(d.surface_samples),
        py::arg("seed") = d.seed, py::arg("threads") = 0, std::forward<Extra>(extra)...);
}

/// Python's json.loads(text).
py::object json_loads(const std::string& text);

/// True for a str or an os.PathLike; its file-system path.
/// Each of \p warnings as a Python UserWarning "source: warning" (an error where the
/// warnings filter makes it one).
void warn_all(const std::vector<std::string>& warnings, const std::string& source);

bool is_path(const py::handle& object);
std::string path_of(const py::handle& object);

}  // namespace medspheres::python
