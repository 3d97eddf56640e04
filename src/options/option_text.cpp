// Option text read into typed values (option_text.h).
#include "medspheres/options/option_text.h"

#include <exception>

#include "medspheres/error.h"

namespace medspheres {

Length parse_length(const std::string& text) {
  Length l;
  std::string number = text;
  if (!number.empty() && (number.back() == 'L' || number.back() == 'l')) {
    l.relative = true;
    number.pop_back();
  }
  std::size_t used = 0;
  try {
    l.value = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (number.empty() || used != number.size())
    throw InputError::option(
        ErrorKind::kOutOfRange, "length", text,
        "'" + text +
            "' is not a length: a number in the mesh's units, or a multiple of "
            "the bounding box's largest side written with an L (0.003L)");
  return l;
}

SolidKind parse_solid_kind(const std::string& text) {
  for (SolidKind k : {SolidKind::kAuto, SolidKind::kWinding, SolidKind::kRobust})
    if (text == to_string(k)) return k;
  throw InputError::option(ErrorKind::kOutOfRange, "solid", text,
                           "must be auto, winding or robust, got '" + text + "'");
}

}  // namespace medspheres
