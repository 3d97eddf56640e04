// Resolving the mesh names of a URDF: relative paths, file:// and package:// URIs.
#include "medspheres/robot/package_path.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <system_error>
#include <vector>

#include "medspheres/error.h"

namespace medspheres {

namespace fs = std::filesystem;

namespace {

constexpr int kPackageSearchDepth = 4;

bool is_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

std::vector<std::string> ros_package_path() {
  std::vector<std::string> entries;
  const char* env = std::getenv("ROS_PACKAGE_PATH");
  if (env == nullptr) return entries;
  std::stringstream in(env);
  std::string entry;
  while (std::getline(in, entry, ':'))
    if (!entry.empty()) entries.push_back(entry);
  return entries;
}

// A folder named `name` holding a package.xml, at most `depth` levels below `dir`, visiting
// subfolders in name order so that the answer does not depend on the file system's order.
std::string find_package_below(const fs::path& dir, const std::string& name, int depth) {
  if (depth < 0) return {};
  std::vector<fs::path> children;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (is_dir(it->path())) children.push_back(it->path());
  std::sort(children.begin(), children.end());
  for (const fs::path& child : children)
    if (child.filename() == name && fs::exists(child / "package.xml", ec)) return child.string();
  for (const fs::path& child : children) {
    const std::string found = find_package_below(child, name, depth - 1);
    if (!found.empty()) return found;
  }
  return {};
}

std::string package_dir(const std::string& uri, const std::string& name,
                        const PackageDirs& packages) {
  const auto given = packages.explicit_dirs.find(name);
  if (given != packages.explicit_dirs.end()) return given->second;
  const std::vector<std::string> entries =
      packages.use_ros_package_path ? ros_package_path() : std::vector<std::string>{};
  for (const std::string& entry : entries) {
    if (is_dir(fs::path(entry) / name)) return (fs::path(entry) / name).string();
    const std::string found = find_package_below(entry, name, kPackageSearchDepth);
    if (!found.empty()) return found;
  }
  throw InputError(uri, "unknown package '" + name + "' (give it with --package " + name + "=DIR" +
                            (entries.empty() ? std::string(", ROS_PACKAGE_PATH is not set")
                                             : std::string(" or add it to ROS_PACKAGE_PATH")) +
                            ")");
}

// A relative path is taken from the URDF's folder; when no file is there, from the nearest of
// its ancestors that has one (descriptions whose meshes sit beside a urdf/ folder, named
// from the description's root as cuRobo's asset_root_path does; yourdfpy searches the same
// folders). With none, the path from the URDF's folder, for the loader to report.
std::string relative_to(const std::string& path, const std::string& urdf_dir) {
  const fs::path p(path);
  if (p.is_absolute()) return p.lexically_normal().string();
  const fs::path direct = (fs::path(urdf_dir) / p).lexically_normal();
  std::error_code ec;
  if (fs::exists(direct, ec)) return direct.string();
  const fs::path from = fs::absolute(fs::path(urdf_dir), ec).lexically_normal();
  if (ec) return direct.string();
  for (fs::path dir = from.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    const fs::path candidate = (dir / p).lexically_normal();
    if (fs::is_regular_file(candidate, ec)) return candidate.string();
    if (dir == dir.root_path()) break;
  }
  return direct.string();
}

}  // namespace

std::string resolve_mesh_path(const std::string& uri, const std::string& urdf_dir,
                              const PackageDirs& packages) {
  if (uri.empty()) throw InputError("mesh filename", "is empty");
  const std::string package_scheme = "package://";
  const std::string file_scheme = "file://";
  if (uri.compare(0, package_scheme.size(), package_scheme) == 0) {
    const std::string rest = uri.substr(package_scheme.size());
    const std::size_t slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    if (name.empty()) throw InputError(uri, "package:// without a package name");
    const std::string dir = package_dir(uri, name, packages);
    if (slash == std::string::npos) return dir;
    return (fs::path(dir) / rest.substr(slash + 1)).lexically_normal().string();
  }
  if (uri.compare(0, file_scheme.size(), file_scheme) == 0)
    return relative_to(uri.substr(file_scheme.size()), urdf_dir);
  const std::size_t colon = uri.find("://");
  if (colon != std::string::npos)
    throw InputError(uri, "unsupported URI scheme '" + uri.substr(0, colon) +
                              "://' (package://, file:// and paths are read)");
  return relative_to(uri, urdf_dir);
}

void add_package_dir(PackageDirs& dirs, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == assignment.size())
    throw InputError::option(ErrorKind::kOutOfRange, "package", "",
                             "expected PKG=DIR, got '" + assignment + "'");
  dirs.explicit_dirs[assignment.substr(0, eq)] = assignment.substr(eq + 1);
}

}  // namespace medspheres
