#pragma once
// What render and view draw, read from the command line: a mesh and its sphere file(s),
// or a robot (URDF + robot-level sphere file, or a robot file alone) at a joint vector.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "medspheres/render/scene.h"

namespace medspheres::cli {

struct SceneArgs {
  std::string model;                  ///< mesh file, URDF, or robot file (.robot.json)
  std::string spheres;                ///< sphere-set file; for a URDF a robot-level sphere file
  std::string outer;                  ///< a mesh's covering set (--outer), optional
  std::string joints;                 ///< "q1,q2,..." or "name=q,..."; empty: the zero pose
  std::vector<std::string> packages;  ///< PKG=DIR
};

struct SceneInput {
  render::Scene scene;
  bool robot = false;
  std::string source;    ///< names the inputs in messages: "SPHERES over MODEL"
  std::string mismatch;  ///< the mesh and sphere-set mismatch warning, or empty
};

/// Registers the positional MODEL [SPHERES] and --outer, --joints, --package on \p sub.
void add_scene_options(CLI::App* sub, SceneArgs& args);

/// The checks of render's and view's output before any work: writable (an output that
/// cannot be written is bad usage), and none of the scene's input files.
/// \throws InputError naming -o.
void check_scene_output(const std::string& output, const SceneArgs& args);

/// Loads the scene; mesh warnings go to stderr.
/// \throws InputError naming the file or option at fault.
SceneInput load_scene_input(const SceneArgs& args);

}  // namespace medspheres::cli
