#pragma once
/// \file
/// A length in a mesh's units, or a multiple of L, the largest side of the mesh's bounding
/// box: what a request holds where the user may write "0.01" or "0.003L" (the text is
/// parsed at the edge, medspheres/options/option_text.h; the library takes this value).

#include <optional>
#include <string>

namespace medspheres {

struct Length {
  double value = 0;
  bool relative = false;  ///< value is a multiple of L
  double in(double largest_side) const { return relative ? value * largest_side : value; }
};

/// The length as a user writes it: "0.01", or "0.003L" when relative.
std::string length_text(const Length& length);

/// Nothing when \p length is absent; otherwise its range: finite and > 0, or >= 0 when
/// \p zero_allowed.
/// \throws InputError (kOutOfRange, field \p field, value length_text) out of that range.
void check_length(const std::optional<Length>& length, const char* field, bool zero_allowed);

}  // namespace medspheres
