#pragma once
// Every file below a folder with its bytes, to compare the outputs of two runs.
#include <filesystem>
#include <map>
#include <string>

#include "support/temp_dir.h"

namespace medspheres::test {

/// Every regular file below \p dir: path relative to it (POSIX separators) -> bytes.
inline std::map<std::string, std::string> file_tree(const std::filesystem::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file())
      out[e.path().lexically_relative(dir).generic_string()] = read_file(e.path().string());
  return out;
}

}  // namespace medspheres::test
