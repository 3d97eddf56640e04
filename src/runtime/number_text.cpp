#include "medspheres/number_text.h"

#include <cstdio>

namespace medspheres {

std::string number_text(double v, int digits) {
  // "%.*g" writes at most digits + 7 characters (a sign, a point, "0.000" or an
  // exponent "e-308"), so 64 bytes hold every useful precision (a double has 17
  // significant digits); snprintf would truncate, not overflow, beyond.
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
  return buffer;
}

}  // namespace medspheres
