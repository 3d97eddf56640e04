#pragma once
// Shared pieces of the medspheres command-line tool.

#include <cstddef>
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "medspheres/error.h"
#include "medspheres/number_text.h"

namespace medspheres::cli {

/// Exit codes: 0 ok, 2 bad usage or bad input, 1 any other failure.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitBadInput = 2;

/// A subcommand registers its options on \p app and returns the function that runs it.
using Runner = std::function<int()>;

Runner register_info(CLI::App& app);
Runner register_bake(CLI::App& app);
Runner register_eval(CLI::App& app);
Runner register_convert(CLI::App& app);
Runner register_robot(CLI::App& app);
Runner register_render(CLI::App& app);
Runner register_view(CLI::App& app);

/// A one-line progress bar on stderr, drawn only when stderr is a terminal and not
/// silenced; redraws at most ten times a second and erases itself when done.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  ~ProgressBar();
  void update(const std::string& stage, std::size_t done, std::size_t total);
  void finish();

 private:
  bool enabled_;
  bool drawn_ = false;
  double last_ = -1.0;
};

/// True when stderr is a terminal (progress bars are drawn only then).
bool stderr_is_terminal();

/// The check of an option read into an unsigned integer (CLI11's ->check): CLI11 would read
/// "-1" as the type's largest value. "must be an integer >= 0, got -1" for a negative text,
/// "" otherwise.
std::string non_negative(const std::string& text);

/// The check of a path option (CLI11's ->check): "must not be empty" for "", "" otherwise.
std::string non_empty(const std::string& text);

/// The flag of a library field: "max_spheres" is --max-spheres.
std::string flag_of(std::string field);

/// The CLI's wording of a library error: fields (and the related fields the problem
/// names) as flags.
std::string message_of(const InputError& e);

/// The exit code of an input error of \p kind.
int exit_code_of(ErrorKind kind);

/// Prints \p e as the CLI words it on stderr; returns its exit code.
int report_input_error(const InputError& e);

}  // namespace medspheres::cli
