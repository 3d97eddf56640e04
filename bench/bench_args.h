#pragma once
// The command line every benchmark shares: CLI11, plus the options and the mesh list that
// several benchmarks have in common.

#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

namespace medspheres::bench {

/// A benchmark's command line. Add options to app() (or through the helpers), then
/// parse(): --help prints the options and exits 0; an unknown option or a bad value
/// prints the problem and the usage and exits 2.
class Args {
 public:
  Args(const std::string& name, const std::string& description);

  CLI::App& app() { return app_; }

  /// Adds the option `flag` (e.g. "--poses") writing to `value`, whose current value is
  /// shown as the default. An unsigned `value` rejects negative numbers (CLI11 alone
  /// would wrap them around).
  template <class T>
  CLI::Option* add(const std::string& flag, T& value, const std::string& description) {
    CLI::Option* option = app_.add_option(flag, value, description)->capture_default_str();
    if constexpr (std::is_unsigned_v<T>) option->check(not_negative());
    return option;
  }

  /// --meshes DIR: a folder holding MANIFEST.tsv; `dir` keeps its value as the default.
  CLI::Option* add_meshes(std::string& dir);
  /// --only SUBSTRING: only meshes whose name contains SUBSTRING.
  CLI::Option* add_only(std::string& only);

  void parse(int argc, char** argv);

 private:
  static CLI::Validator not_negative();

  CLI::App app_;
};

/// True when `only` is empty or `name` contains it.
bool selected(const std::string& name, const std::string& only);

struct MeshFile {
  std::string name;  ///< "examples/<file>", or the file as MANIFEST.tsv names it
  std::string path;
};

/// examples/knot1.off and examples/eight.off, then the closed meshes of DIR/MANIFEST.tsv in
/// its order (only the "classic" ones when `classic_only`); nothing from DIR when it is empty.
std::vector<MeshFile> bench_meshes(const std::string& dir, bool classic_only);

/// Starts the program again with OMP_WAIT_POLICY=passive when it is unset: threads waiting
/// at OpenMP's barriers then sleep rather than spin, which on a machine shared with other
/// work would take the cores the others need and inflate the bench's own seconds (the
/// OpenMP runtime reads the setting when it loads). Returns only when it is already set or
/// the restart failed.
void restart_with_passive_openmp(char** argv);

}  // namespace medspheres::bench
