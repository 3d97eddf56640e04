#include "cli_common.h"

#include <cstdio>
#include <sstream>

#include <unistd.h>

namespace medspheres::cli {

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

std::string fmt(double v, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << v;
  return s.str();
}

}  // namespace medspheres::cli
