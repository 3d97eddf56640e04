// Lengths in a mesh's units or in L (length.h).
#include "medspheres/mesh/length.h"

#include <cmath>

#include "medspheres/error.h"
#include "medspheres/number_text.h"

namespace medspheres {

std::string length_text(const Length& l) {
  return number_text(l.value) + (l.relative ? "L" : "");
}

void check_length(const std::optional<Length>& l, const char* field, bool zero_allowed) {
  if (!l) return;
  const bool ok = std::isfinite(l->value) && (zero_allowed ? l->value >= 0.0 : l->value > 0.0);
  if (!ok)
    throw InputError::option(ErrorKind::kOutOfRange, field, length_text(*l),
                             std::string("must be a finite length ") +
                                 (zero_allowed ? ">= 0" : "> 0") + ", got " + length_text(*l));
}

}  // namespace medspheres
