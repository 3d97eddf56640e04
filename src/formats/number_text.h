#pragma once
// Numbers in the text formats: written in the shortest form that reads back to the same
// double (at most 17 significant digits), read back exactly.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "medspheres/sphere_set.h"

namespace medspheres::formats {

/// The shortest decimal text of \p v that reads back bit-identical ("0.1", "1e-300").
std::string exact_number(double v);

/// \p values separated by single spaces ("x y z").
std::string exact_numbers(const std::vector<double>& values);

/// The whitespace-separated numbers of \p text, or nothing when a word is not a number.
std::optional<std::vector<double>> parse_numbers(std::string_view text);

}  // namespace medspheres::formats
