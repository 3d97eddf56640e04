#pragma once
// Numbers in the messages of the bake component: six significant digits, as printf's %g.

#include <cstdio>
#include <string>

namespace medspheres {

inline std::string number_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace medspheres
