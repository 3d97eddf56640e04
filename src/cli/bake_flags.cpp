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

void set_dilation(const DilationFlags& flags, BakeRequest& request) {
  request.dilate = flags.dilate;
  request.vertex_tolerance = length_option(flags.vertex_tolerance, "vertex_tolerance");
  request.max_protrusion = length_option(flags.max_protrusion, "max_protrusion");
  request.cover = length_option(flags.cover, "cover");
  request.seed = flags.seed;
}

}  // namespace medspheres::cli
