#pragma once
// The bake options that `bake` and `robot` share, from their flags.
#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "medspheres/bake/bake_pipeline.h"

namespace medspheres::cli {

/// The length flag of the request field \p field, parsed (a number, or a multiple of L
/// written with an L); an error names the field, which the CLI reports as its flag.
std::optional<Length> length_option(const std::optional<std::string>& text, const char* field);

/// The dilation flags (--dilate, --vertex-tolerance, --max-protrusion, --cover, --seed).
struct DilationFlags {
  bool dilate = false;
  std::optional<std::string> vertex_tolerance, max_protrusion, cover;
  std::uint64_t seed = BakeRequest{}.seed;
};

/// Sets the request's dilation from \p flags (lengths parsed; ranges are validate()'s).
void set_dilation(const DilationFlags& flags, BakeRequest& request);

/// The solid flags (--solid, --robust-resolution, --robust-thickness).
struct SolidFlags {
  std::string solid = "auto";
  int robust_resolution = RobustSolidOptions{}.resolution;
  std::optional<std::string> robust_thickness;
};

/// Adds the solid flags to \p sub.
void add_solid_flags(CLI::App* sub, SolidFlags& flags);

/// Sets the request's solid from \p flags (an unknown --solid is an InputError).
void set_solid(const SolidFlags& flags, BakeRequest& request);

}  // namespace medspheres::cli
