#pragma once
// The solid flags of bake, eval and robot, registered on a subcommand.

#include <CLI/CLI.hpp>

#include "medspheres/options/bake_flags.h"

namespace medspheres::cli {

/// Adds --solid, --robust-resolution and --robust-thickness to \p sub, bound to \p flags.
void add_solid_flags(CLI::App* sub, SolidFlags& flags);

}  // namespace medspheres::cli
