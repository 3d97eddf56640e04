#pragma once
/// \file
/// Any sphere file medspheres reads or writes, and the conversion between them (what
/// `medspheres convert` runs).
///
/// Formats and their extensions:
/// | format   | extension                 | holds                                 |
/// |----------|---------------------------|---------------------------------------|
/// | spheres  | .json (.spheres.json)     | one set: medspheres' sphere-set file  |
/// | robot    | .robot.json               | medspheres' robot file (tree, sets)   |
/// | curobo   | .yml, .yaml               | per link                              |
/// | xrdf     | .xrdf                     | per link                              |
/// | urdf     | .urdf                     | per link (spherized URDF)             |
/// | srdf     | .srdf                     | per link                              |
/// | foam     | .foam.json                | one set (list of levels) or per link  |
/// | sph      | .sph                      | one set (spheretree)                  |
/// A plain ".json" that is read is recognised by its content (robot file, sphere-set file,
/// or foam's list or database); written, it is a sphere-set file.
///
/// A document with a robot model writes the planner keys of its PlannerSetup (or the
/// default one) into the cuRobo, XRDF and SRDF files (planner_options.h).
///
/// Conversion: a per-link file written to a one-set format takes the link that
/// WriteOptions::link names (or its only link); a one-set file written to a per-link
/// format becomes that one link; a per-link file written to a per-link format takes every
/// link, and a link named then is refused (it would go unused). foam output is foam's one-mesh list
/// for a one-set input or when a link is named, its per-link database otherwise. A robot file is
/// written only from a robot file (it needs the kinematic tree); a spherized URDF needs the robot's
/// URDF (the input's, or WriteOptions::urdf_text). An XRDF is not written from a robot model
/// without an actuated joint (writes_xrdf): cuRobo's loaders refuse an XRDF with an empty cspace.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "medspheres/formats/curobo_yaml.h"
#include "medspheres/formats/robot_spheres.h"
#include "medspheres/robot_model.h"
#include "medspheres/sphere_set.h"

namespace medspheres::formats {

enum class SphereFormat { kSphereSet, kRobot, kCurobo, kXrdf, kUrdf, kSrdf, kFoam, kSph };

/// "spheres", "robot", "curobo", "xrdf", "urdf", "srdf", "foam", "sph".
const char* sphere_format_name(SphereFormat format);

/// The format named \p name. \throws InputError naming \p option and the known names.
SphereFormat parse_sphere_format(const std::string& name, const std::string& option);

/// The format of \p path from its extension (".json" is a sphere-set file).
/// \throws InputError naming \p path when the extension is none of the above.
SphereFormat sphere_format_of_path(const std::string& path);

/// What one file held.
struct SphereDocument {
  std::optional<SphereSet> set;     ///< a one-set file
  RobotSpheres links;               ///< a per-link file (empty for a one-set file)
  std::optional<RobotModel> model;  ///< a robot file's whole model
  std::string urdf_text;            ///< a URDF's text
  std::string robot_name;           ///< when the file names the robot
};

/// The document of a robot model: its chosen sets per link, the model itself, and the
/// URDF it came from (for a spherized URDF). What the robot command writes each format from.
/// \throws InputError naming \p source when no link has spheres of the chosen kind.
SphereDocument robot_document(const RobotModel& model, SphereChoice choice,
                              const std::string& urdf_text, const std::string& source);

struct ReadOptions {
  SphereChoice choice = SphereChoice::kOuter;  ///< the set a robot file gives
  int level = -1;  ///< the level of a .sph or foam file, from 0 at the root; -1: the last
};

struct WriteOptions {
  std::string link;       ///< the link a one-set output takes, or names a one-set input
  std::string urdf_text;  ///< the URDF a spherized URDF is made from
  std::string urdf_source = "--urdf";  ///< its name in error messages (its path)
  std::string robot_name;              ///< the SRDF's robot name (default: the input's, or "robot")
  /// Which cuRobo file the curobo format writes (v2's configuration by default).
  CuroboLayout curobo = CuroboLayout::kV2;
  /// A cuRobo configuration's urdf_path (of a robot model's document); not written when empty.
  std::string urdf_path;
};

/// Reads \p path as \p format (nullopt: from the extension and, for ".json", the content).
/// \throws InputError naming the file and the problem, or the option "level" below -1.
SphereDocument read_sphere_document(const std::string& path,
                                    std::optional<SphereFormat> format = std::nullopt,
                                    const ReadOptions& options = {});

/// The text of \p doc in \p format. \throws InputError naming the option ("--link",
/// "--urdf") or the problem when the conversion is not possible.
std::string sphere_document_text(const SphereDocument& doc, SphereFormat format,
                                 const WriteOptions& options = {});

/// The one set of \p doc: a one-set file's set (\p link is then ignored), or the spheres of
/// the link \p link names, or of the only link when \p link is empty.
/// \throws InputError (option \p link_field) for a link the file has no spheres for, or an
///   empty \p link when the file has several links.
std::vector<Sphere> one_set_of(const SphereDocument& doc, const std::string& link,
                               const std::string& link_field = "link");

/// The spheres per link of the per-link file \p path (read_sphere_document), link -> spheres.
/// \throws InputError naming the option \p option (its value \p path) for a one-set file,
///   and as read_sphere_document.
std::map<std::string, std::vector<Sphere>> read_link_sphere_map(const std::string& path,
                                                                const std::string& option);

/// Writes sphere_document_text atomically to \p path: nothing is written on error. A
/// writer's InputError that names only its format (".sph") names \p path instead.
void write_sphere_document(const std::string& path, const SphereDocument& doc, SphereFormat format,
                           const WriteOptions& options = {});

}  // namespace medspheres::formats
