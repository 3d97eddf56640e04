#pragma once
/// \file
/// The files a robot bake writes into its output folder (what `medspheres robot -o DIR`
/// and the Python module's bake_robot write): one file per chosen format, named after the
/// robot (robot.json, curobo.yml, xrdf, spherized.urdf, srdf, foam.json; .sph holds one
/// set, so it gets a folder "sph" with one file per link). The curobo format writes three
/// files: curobo.yml (cuRobo v2's configuration), curobo_v1.yml (v1's) and
/// curobo_spheres.yml (the spheres alone, at the top level, for a configuration of one's
/// own to name by path). Beside the robot file, a model with a self-collision matrix also
/// gets self_collision.txt (self_collision_report.h), the matrix for people. The folder is replaced
/// as a whole: the files are written to a fresh folder beside it, which is then moved into place,
/// so a failure leaves the old folder untouched.
///
/// Errors: InputError named by the fields "format" and "set", or by the folder.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/formats/robot_spheres.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/robot_model.h"

namespace medspheres::formats {

/// The formats that hold a robot: robot, curobo, xrdf, urdf, srdf, foam, sph.
const std::vector<SphereFormat>& robot_formats();

/// The formats named \p names, duplicates dropped, in the order given; every robot format
/// when \p names is empty. \throws InputError (field "format") for an unknown name or a
/// one-set format.
std::vector<SphereFormat> robot_output_formats(const std::vector<std::string>& names);

/// "auto" (nullopt: decided by robot_output_choice), "inner" or "outer".
/// \throws InputError (field "set") for anything else.
std::optional<SphereChoice> parse_set_choice(const std::string& set);

/// The set the planner formats carry: \p chosen when given, else the covering set where
/// any link has one (a planner must not miss a collision), else the inner set.
SphereChoice robot_output_choice(std::optional<SphereChoice> chosen, const RobotModel& model);

/// \p out must be a folder or nothing, in a folder that exists.
/// \throws InputError naming \p out otherwise.
void check_output_dir(const std::string& out);

/// The files of the folder write_robot_outputs writes: path in the folder (POSIX
/// separators, "sph/LINK.sph" for .sph) -> bytes. \throws as write_robot_outputs.
std::map<std::string, std::string> robot_output_files(const std::vector<SphereFormat>& chosen,
                                                      const RobotModel& model, SphereChoice choice,
                                                      const std::string& urdf);

/// Replaces the folder \p out as a whole (file comment) with \p files (path in the
/// folder -> bytes, as robot_output_files gives). \throws Error when it cannot be replaced.
void write_output_folder(const std::string& out, const std::map<std::string, std::string>& files);

/// Writes \p model's spheres (the \p choice set) in every format of \p chosen to the
/// folder \p out, replacing it as a whole (file comment). \p urdf is the robot's URDF
/// path (for the spherized URDF). \throws InputError as the writers, Error when the
/// folder cannot be replaced.
void write_robot_outputs(const std::string& out, const std::vector<SphereFormat>& chosen,
                         const RobotModel& model, SphereChoice choice, const std::string& urdf);

}  // namespace medspheres::formats
