// medspheres.InputError: the library's InputError as a ValueError with its parts.
#include <Python.h>

#include "medspheres/error.h"
#include "py_common.h"

namespace medspheres::python {

void register_errors(py::module_& m) {
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  input_error.doc() =
      "Bad input (a file, an option): a ValueError whose message is the command line's, "
      "with options named as the keywords.\n\nAttributes: kind ('out_of_range', "
      "'file_missing', ...), file, field (the keyword at fault, '' for a file's problem), "
      "value, problem.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      const auto type = py::reinterpret_borrow<py::object>(input_error.ptr());
      py::object error = type(e.what());
      error.attr("kind") = to_string(e.kind());
      error.attr("file") = e.file();
      error.attr("field") = e.field();
      error.attr("value") = e.value();
      error.attr("problem") = e.problem();
      PyErr_SetObject(input_error.ptr(), error.ptr());
    }
  });
}

}  // namespace medspheres::python
