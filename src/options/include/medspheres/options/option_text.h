#pragma once
/// \file
/// Option text as a user writes it ("0.003L", "robust"), read into the library's typed
/// values. The library itself takes only numbers, enums and paths.

#include <string>

#include "medspheres/mesh/length.h"
#include "medspheres/mesh/robust_solid.h"

namespace medspheres {

/// "0.01" (absolute) or "0.003L" (relative; "l" too). Ranges are checked where the length
/// is used (validate(), check_solid_request()).
/// \throws InputError (kOutOfRange, field "length", value \p text) for anything else.
Length parse_length(const std::string& text);

/// The kind named \p text ("auto", "winding", "robust": to_string of each).
/// \throws InputError (kOutOfRange, field "solid", value \p text) for any other text.
SolidKind parse_solid_kind(const std::string& text);

}  // namespace medspheres
