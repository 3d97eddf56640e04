#pragma once
// Shared pieces of the medspheres command-line tool.

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace medspheres::cli {

/// Exit codes: 0 ok, 2 bad usage or bad input, 1 any other failure.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitBadInput = 2;

/// A subcommand registers its options on \p app and returns the function that runs it.
using Runner = std::function<int()>;

Runner register_info(CLI::App& app);

/// True when stderr is a terminal (progress bars are drawn only then).
bool stderr_is_terminal();

/// Formats a double for humans: up to \p digits significant digits.
std::string fmt(double v, int digits = 6);

}  // namespace medspheres::cli
