#pragma once
// The bake options that `bake` and `robot` share, from their flags.
#include <optional>
#include <string>

#include "medspheres/bake/bake_pipeline.h"

namespace medspheres::cli {

/// The length flag of the request field \p field, parsed (a number, or a multiple of L
/// written with an L); an error names the field, which the CLI reports as its flag.
std::optional<Length> length_option(const std::optional<std::string>& text, const char* field);

}  // namespace medspheres::cli
