#include "support/run_command.h"

#include <cstdio>
#include <stdexcept>

#include <sys/wait.h>

#include "support/temp_dir.h"

namespace medspheres::test {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

CommandResult run_command(const std::string& command) {
  TempDir dir;
  const std::string err_path = dir.file("stderr");
  const std::string full = command + " 2>" + shell_quote(err_path);
  CommandResult r;
  std::FILE* pipe = ::popen(full.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("popen failed: " + command);
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = read_file(err_path);
  return r;
}

}  // namespace medspheres::test
