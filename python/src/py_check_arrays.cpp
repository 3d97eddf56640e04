#include "py_check_arrays.h"

namespace medspheres::python {

check::Simd simd_of(const std::string& simd) {
  if (simd == "auto") return check::Simd::automatic;
  if (simd == "scalar") return check::Simd::scalar;
  if (simd == "avx2") return check::Simd::avx2;
  throw py::value_error("simd: expected 'auto', 'scalar' or 'avx2', not '" + simd + "'");
}

py::array_t<double, py::array::c_style | py::array::forcecast> configurations(const py::handle& q,
                                                                              std::size_t dof,
                                                                              const char* what) {
  return float_rows(q, static_cast<py::ssize_t>(dof), std::string(what) + " (joint_names order)");
}

py::array_t<std::uint8_t> verdict_array(const std::vector<check::Verdict>& v) {
  py::array_t<std::uint8_t> out(static_cast<py::ssize_t>(v.size()));
  auto w = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < v.size(); ++i) w(py::ssize_t(i)) = static_cast<std::uint8_t>(v[i]);
  return out;
}

}  // namespace medspheres::python
