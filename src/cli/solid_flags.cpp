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

void add_cover_search_flags(CLI::App* sub, CoverSearch& search, const std::string& what) {
  sub->add_option("--protrusion-allowance", search.protrusion_allowance,
                  what +
                      ": how far the volume stage may raise the largest protrusion, a "
                      "fraction of it (0: never; lower P, more volume outside)")
      ->capture_default_str();
  sub->add_option("--protrusion-restarts", search.protrusion_restarts,
                  what +
                      ": perturbed restarts of the protrusion stage, each kept when it "
                      "sticks out less (time for a lower P; docs/covers.md)")
      ->capture_default_str();
  sub->add_option("--balance-rounds", search.balance_rounds,
                  what +
                      ": balancing rounds at most after each run of minimax rounds "
                      "(40: P about 5% lower at 1.2 to 1.3 times the time)")
      ->capture_default_str();
}

}  // namespace medspheres::cli
