#pragma once
// Runs a shell command and captures its exit code, standard output and standard error.

#include <string>

namespace medspheres::test {

struct CommandResult {
  int exit_code = -1;
  std::string out;  ///< standard output
  std::string err;  ///< standard error
};

/// Runs \p command through /bin/sh. Standard error is captured through a temporary file.
CommandResult run_command(const std::string& command);

/// Quotes \p s for /bin/sh.
std::string shell_quote(const std::string& s);

#ifdef MEDSPHERES_CLI
/// Runs the medspheres command-line tool of this build with \p args (already quoted);
/// with \p seconds > 0 under that time limit, so that a run that never ends fails the
/// test (exit 124) instead of hanging the suite.
inline CommandResult run_cli(const std::string& args, int seconds = 0) {
  const std::string limit = seconds > 0 ? "timeout " + std::to_string(seconds) + " " : "";
  return run_command(limit + shell_quote(MEDSPHERES_CLI) + " " + args);
}
#endif

}  // namespace medspheres::test
