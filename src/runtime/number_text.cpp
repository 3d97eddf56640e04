#include "medspheres/number_text.h"

#include <charconv>
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

std::string exact_number_text(double v) {
  char buffer[32];
  // std::to_chars without a precision gives the shortest round-trip form.
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

std::string count_text(std::size_t n, const std::string& noun, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? noun : plural.empty() ? noun + "s" : plural);
}

}  // namespace medspheres
