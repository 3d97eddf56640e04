#include "py_common.h"

#include <climits>
#include <cmath>
#include <stdexcept>

#include "medspheres/error.h"
#include "medspheres/number_text.h"

namespace medspheres::python {

py::array_t<double, py::array::c_style | py::array::forcecast> float_rows(const py::handle& a,
                                                                          py::ssize_t columns,
                                                                          const std::string& what) {
  auto rows = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!rows || rows.ndim() != 2 || rows.shape(1) != columns)
    throw py::value_error(what + ": expected an n x " + std::to_string(columns) +
                          " array of numbers");
  return rows;
}

SphereSet sphere_set_of_array(const py::handle& array, const std::string& what) {
  const auto rows = float_rows(array, 4, what);
  SphereSet set;
  const auto r = rows.unchecked<2>();
  set.spheres.resize(static_cast<std::size_t>(rows.shape(0)));
  for (py::ssize_t i = 0; i < rows.shape(0); ++i) {
    Sphere& s = set.spheres[static_cast<std::size_t>(i)];
    s.center = Eigen::Vector3d(r(i, 0), r(i, 1), r(i, 2));
    s.radius = r(i, 3);
  }
  return set;
}

SphereSet sphere_set_of(const py::handle& object, const std::string& what) {
  if (py::isinstance<SphereSet>(object)) return object.cast<const SphereSet&>();
  return sphere_set_of_array(object, what);
}

py::array_t<double> spheres_array(const std::vector<Sphere>& spheres) {
  py::array_t<double> out({static_cast<py::ssize_t>(spheres.size()), py::ssize_t{4}});
  auto w = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    const auto k = static_cast<py::ssize_t>(i);
    w(k, 0) = spheres[i].center.x();
    w(k, 1) = spheres[i].center.y();
    w(k, 2) = spheres[i].center.z();
    w(k, 3) = spheres[i].radius;
  }
  return out;
}

TriangleMesh mesh_of_arrays(const py::handle& pair) {
  const py::tuple t = py::tuple(py::reinterpret_borrow<py::object>(pair));
  if (t.size() != 2) throw py::value_error("mesh: expected a path or a pair (vertices, triangles)");
  const auto v = float_rows(t[0], 3, "mesh vertices");
  auto f = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(t[1]);
  if (!f || f.ndim() != 2 || f.shape(1) != 3)
    throw py::value_error("mesh triangles: expected an m x 3 array of vertex indices");
  TriangleMesh mesh;
  const auto vr = v.unchecked<2>();
  for (py::ssize_t i = 0; i < v.shape(0); ++i)
    mesh.vertices.emplace_back(vr(i, 0), vr(i, 1), vr(i, 2));
  const auto fr = f.unchecked<2>();
  for (py::ssize_t i = 0; i < f.shape(0); ++i) {
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const long long x = fr(i, k);
      if (x < INT_MIN || x > INT_MAX)
        throw py::value_error("mesh triangles: triangle " + std::to_string(i) +
                              " has an index out of range");
      tri[static_cast<std::size_t>(k)] = static_cast<int>(x);
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

Eigen::Isometry3d pose_of(const py::handle& pose, const char* what) {
  if (pose.is_none()) return Eigen::Isometry3d::Identity();
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(pose);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw py::value_error(std::string(what) + ": expected a 4 x 4 homogeneous transform");
  const auto entries = a.unchecked<2>();
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = entries(i, j);
  if (!m.allFinite()) throw py::value_error(std::string(what) + ": has a non-finite entry");
  if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1)
    throw py::value_error(std::string(what) + ": the last row must be 0, 0, 0, 1");
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  if (!(r.transpose() * r).isIdentity(1e-9) || !(r.determinant() > 0))
    throw py::value_error(std::string(what) + ": the rotation is not orthonormal with det +1");
  Eigen::Isometry3d x;
  x.matrix() = m;
  return x;
}

std::optional<std::string> length_text(const py::handle& value, const char* field) {
  if (value.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  const bool real = !py::isinstance<py::bool_>(value) &&
                    py::isinstance(value, py::module_::import("numbers").attr("Real"));
  if (real) return exact_number_text(py::float_(py::reinterpret_borrow<py::object>(value)));
  const std::string type = py::str(value.get_type().attr("__name__"));
  throw InputError::option(ErrorKind::kOutOfRange, field, py::str(py::repr(value)),
                           "must be a length: a number, or text such as '0.003L' (a multiple "
                           "of L), got a " +
                               type);
}

std::map<std::string, SphereSet> link_spheres_of(const py::handle& mapping,
                                                 const std::string& what) {
  if (!py::isinstance<py::dict>(mapping))
    throw py::type_error(what + ": expected a path or a dict link name -> spheres");
  std::map<std::string, SphereSet> out;
  for (const auto& [link, spheres] : py::reinterpret_borrow<py::dict>(mapping)) {
    const std::string name = py::str(link);
    out[name] = sphere_set_of(spheres, what + "['" + name + "']");
  }
  return out;
}

py::object json_loads(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

bool is_path(const py::handle& object) {
  return py::isinstance<py::str>(object) ||
         py::isinstance(object, py::module_::import("os").attr("PathLike"));
}

std::string path_of(const py::handle& object) {
  return py::module_::import("os").attr("fspath")(object).cast<std::string>();
}

void warn_all(const std::vector<std::string>& warnings, const std::string& source) {
  for (const std::string& w : warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, (source + ": " + w).c_str(), 2) != 0)
      throw py::error_already_set();  // warnings turned into errors
}

}  // namespace medspheres::python
