#pragma once
// Where this build's sources, programs and shared meshes are, for the tests and benchmarks.
//
// Their programs are compiled with this header forced in (-include) and with
// MEDSPHERES_SOURCE_DIR, MEDSPHERES_CLI, MEDSPHERES_ROBOT_DISTANCE and
// MEDSPHERES_SHARED_MESHES defined as calls of these functions, never as the paths
// themselves: a path on a compile line is part of the compiler cache's key, so that a clone
// in another folder would compile every file that uses one again. The paths are compiled
// once, into the build's generated build_paths.cpp (the top CMakeLists.txt).

namespace medspheres::build_paths {

/// The repository's root, absolute.
const char* source_dir();
/// This build's medspheres program ("" in a build without it).
const char* cli();
/// This build's examples/robot_distance program ("" in a build without the tests).
const char* robot_distance();
/// The folder of optional shared meshes with a MANIFEST.tsv ("" when there is none).
const char* shared_meshes();

}  // namespace medspheres::build_paths
