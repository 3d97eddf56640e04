#include "solid_flags.h"

namespace medspheres::cli {

void add_solid_flags(CLI::App* sub, SolidFlags& flags) {
  sub->add_option("--solid", flags.solid,
                  "Solid: auto (bake: the winding number's, robust when it is ambiguous; eval: "
                  "the one the sphere file records), winding, robust (docs/baking.md: Solids)")
      ->capture_default_str();
  sub->add_option("--robust-resolution", flags.robust_resolution,
                  "Robust solid: grid cells along the longest side, in [8, 1024]; 0: the finest "
                  "whose boundary has at most 24000 triangles")
      ->capture_default_str();
  sub->add_option("--robust-thickness", flags.robust_thickness,
                  "Robust solid: extra wall thickness that closes gaps (length or 0.01L; "
                  "default 0)");
}

}  // namespace medspheres::cli
