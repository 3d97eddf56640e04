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

void add_solid_flags(CLI::App* sub, SolidFlags& flags) {
  sub->add_option("--solid", flags.solid,
                  "Solid: auto (bake: the winding number's, robust when it is ambiguous; eval: "
                  "the one the sphere file records), winding, robust (README: Solids)")
      ->capture_default_str();
  sub->add_option("--robust-resolution", flags.robust_resolution,
                  "Robust solid: grid cells along the longest side, in [8, 1024]")
      ->capture_default_str();
  sub->add_option("--robust-thickness", flags.robust_thickness,
                  "Robust solid: extra wall thickness that closes gaps (length or 0.01L; "
                  "default 0)");
}

void set_solid(const SolidFlags& flags, BakeRequest& request) {
  request.solid = parse_solid_kind(flags.solid);
  request.robust.resolution = flags.robust_resolution;
  request.robust_thickness = length_option(flags.robust_thickness, "robust_thickness");
}

}  // namespace medspheres::cli
