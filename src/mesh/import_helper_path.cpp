#include "import_helper_path.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>

#include "medspheres/error.h"

// Set by src/mesh/CMakeLists.txt: the helper's file name, the install's bin folder relative
// to its lib folder, and the bin folder of the install prefix.
#ifndef MEDSPHERES_IMPORT_HELPER_NAME
#define MEDSPHERES_IMPORT_HELPER_NAME "medspheres-import"
#endif
#ifndef MEDSPHERES_LIBDIR_TO_BINDIR
#define MEDSPHERES_LIBDIR_TO_BINDIR "../bin"
#endif

namespace medspheres::detail {

namespace {

namespace fs = std::filesystem;

bool is_executable_file(const fs::path& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
}

// The folder of the binary (program, shared library or module) that holds this code.
fs::path this_binary_folder() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&import_helper_path), &info) == 0 || !info.dli_fname ||
      !*info.dli_fname)
    return {};
  std::error_code ec;
  const fs::path file = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path() : file.parent_path();
}

fs::path running_program_folder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

// The folders to look in, in order, without repeats or empty entries.
std::vector<fs::path> search_folders() {
  std::vector<fs::path> folders;
  auto add = [&](fs::path dir) {
    if (dir.empty()) return;
    dir = dir.lexically_normal();
    for (const fs::path& f : folders)
      if (f == dir) return;
    folders.push_back(std::move(dir));
  };
  const fs::path binary = this_binary_folder();
  add(binary);
  if (!binary.empty()) add(binary / MEDSPHERES_LIBDIR_TO_BINDIR);
  add(running_program_folder());
#ifdef MEDSPHERES_INSTALL_FULL_BINDIR
  add(fs::path(MEDSPHERES_INSTALL_FULL_BINDIR));
#endif
  return folders;
}

}  // namespace

std::string import_helper_path(const std::string& subject) {
  const std::string prefix = subject + ": ";
  const char* chosen = std::getenv(kImportHelperVariable);
  if (chosen && *chosen) {
    if (!is_executable_file(chosen))
      throw Error(prefix + "cannot start the import process: " + kImportHelperVariable + "=" +
                  chosen + " is not an executable file");
    return chosen;
  }
  std::string looked;
  for (const fs::path& dir : search_folders()) {
    const fs::path candidate = dir / MEDSPHERES_IMPORT_HELPER_NAME;
    if (is_executable_file(candidate)) return candidate.string();
    looked += (looked.empty() ? "" : ", ") + dir.string();
  }
  throw Error(prefix + "cannot start the import process: the program " +
              MEDSPHERES_IMPORT_HELPER_NAME + " of the medspheres installation is in none of " +
              looked + "; install it beside the medspheres program, name it in " +
              kImportHelperVariable + ", or load with MeshLoadOptions::isolate_import = false");
}

}  // namespace medspheres::detail
