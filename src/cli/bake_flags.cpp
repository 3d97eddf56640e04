#include "bake_flags.h"

#include "medspheres/error.h"

namespace medspheres::cli {

std::optional<Length> length_option(const std::optional<std::string>& text, const char* field) {
  if (!text) return std::nullopt;
  try {
    return parse_length(*text);
  } catch (const InputError& e) {
    throw e.with_field(field);
  }
}

}  // namespace medspheres::cli
