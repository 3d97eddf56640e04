#pragma once
/// \file
/// Where the mesh files a URDF names live: `filename` attributes as robot descriptions
/// write them, resolved to paths on this machine.

#include <map>
#include <string>

namespace medspheres {

/// Package folders: `package://PKG/rest` resolves to `<folder of PKG>/rest`.
struct PackageDirs {
  /// Given explicitly (the CLI's --package PKG=DIR); looked up first.
  std::map<std::string, std::string> explicit_dirs;
  /// Then every folder of ROS_PACKAGE_PATH (':'-separated) is searched: PKG is the
  /// folder `<entry>/PKG`, or any folder below an entry (at most 4 levels deep) named PKG
  /// that holds a package.xml. The first match in the order of the entries wins.
  bool use_ros_package_path = true;
};

/// The path of the file that \p uri names, for a URDF in folder \p urdf_dir:
/// - `package://PKG/rest`: through \p packages (above);
/// - `file:///abs/path` or `file://rel/path`: the path after the scheme (a relative one is
///   taken relative to \p urdf_dir);
/// - anything else without a scheme: a path, relative to \p urdf_dir unless absolute.
/// A relative path that names no file from \p urdf_dir is taken from the nearest ancestor
/// folder of \p urdf_dir where it names one (meshes named from a description's root, as
/// cuRobo's asset_root_path and yourdfpy's search take them). The file itself is not opened
/// (a missing file is the loader's error, with the path from \p urdf_dir).
/// \throws InputError (source: \p uri) for an empty name, an unknown package (the message
///   says where it was looked for), `package://` without a package name, or another
///   scheme (http://, model://, ...).
std::string resolve_mesh_path(const std::string& uri, const std::string& urdf_dir,
                              const PackageDirs& packages);

/// Parses a `PKG=DIR` argument into \p dirs.
/// \throws InputError (source "--package") unless the text has a non-empty PKG and DIR.
void add_package_dir(PackageDirs& dirs, const std::string& assignment);

}  // namespace medspheres
