#pragma once
// Numbers in the text formats: written in the shortest form that reads back to the same
// double (at most 17 significant digits), read back exactly.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "medspheres/number_text.h"
#include "medspheres/sphere_set.h"

namespace medspheres::formats {

/// \p values separated by single spaces ("x y z").
std::string exact_numbers(const std::vector<double>& values);

/// The whitespace-separated numbers of \p text, or nothing when a word is not a number.
std::optional<std::vector<double>> parse_numbers(std::string_view text);

}  // namespace medspheres::formats
