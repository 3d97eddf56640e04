// The medspheres Python module: bindings over the library, no logic of their own.
#include "medspheres/version.h"
#include "py_common.h"

PYBIND11_MODULE(_medspheres, m) {
  namespace python = medspheres::python;
  m.doc() = "medspheres: medial sphere sets of meshes and robots, their fit, and queries.";
  m.attr("__version__") = MEDSPHERES_VERSION_STRING;
  python::register_errors(m);
  python::register_sphere_set(m);
  python::register_bake(m);
  python::register_robot(m);
  python::register_queries(m);
  python::register_check(m);
}
