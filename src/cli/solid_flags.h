#pragma once
// The solid flags of bake, eval and robot, and the cover search flags of bake and robot,
// registered on a subcommand; bench_budget and bench_self_collision register the same cover
// search flags (library medspheres_cli_flags).

#include <CLI/CLI.hpp>

#include "medspheres/options/bake_flags.h"

namespace medspheres::cli {

/// Adds --solid, --robust-resolution and --robust-thickness to \p sub, bound to \p flags.
void add_solid_flags(CLI::App* sub, SolidFlags& flags);

/// Adds --protrusion-allowance, --protrusion-restarts and --balance-rounds to \p sub, bound to
/// \p search; \p what names the sets they apply to.
void add_cover_search_flags(CLI::App* sub, CoverSearch& search, const std::string& what);

}  // namespace medspheres::cli
