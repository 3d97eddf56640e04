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

}  // namespace medspheres::test
