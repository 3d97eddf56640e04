#pragma once
// What the robot checkers' bindings share (py_check.cpp, py_certified.cpp): configurations
// in, verdicts out, the SIMD choice by name.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "medspheres/check/robot_checker.h"
#include "py_common.h"

namespace medspheres::python {

/// CertifiedChecker (py_certified.cpp); register_check calls it, after CheckScene.
void register_certified(py::module_& m);

/// "auto", "scalar" or "avx2"; ValueError otherwise.
check::Simd simd_of(const std::string& simd);

/// An n x dof float64 C-contiguous array of configurations; ValueError naming \p what.
py::array_t<double, py::array::c_style | py::array::forcecast> configurations(const py::handle& q,
                                                                              std::size_t dof,
                                                                              const char* what);

/// The verdicts as a uint8 array (0 free, 1 colliding, 2 undecided).
py::array_t<std::uint8_t> verdict_array(const std::vector<check::Verdict>& v);

}  // namespace medspheres::python
