#pragma once
// Files for tests: a fresh temporary directory per test, removed when the object dies;
// reading a whole file; the bundled example meshes.

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

namespace medspheres::test {

class TempDir {
 public:
  TempDir() {
    static std::atomic_int counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("medspheres-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string file(const std::string& name) const { return (path_ / name).string(); }

  /// Writes \p contents to \p name in this directory and returns its path.
  std::string write(const std::string& name, const std::string& contents) const {
    const std::string p = file(name);
    std::ofstream(p, std::ios::binary) << contents;
    return p;
  }

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The whole content of \p path, byte for byte (empty if it cannot be read).
inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

#ifdef MEDSPHERES_SOURCE_DIR
/// The path of a bundled example mesh, e.g. example_mesh("eight.off").
inline std::string example_mesh(const std::string& name) {
  return std::string(MEDSPHERES_SOURCE_DIR) + "/examples/data/" + name;
}
#endif

}  // namespace medspheres::test
