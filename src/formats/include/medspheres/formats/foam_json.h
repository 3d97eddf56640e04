#pragma once
/// \file
/// foam's JSON (CoMMALab/foam, which runs spheretree's medial method).
///
/// One mesh: a list of levels, each {"mean": e, "best": e, "worst": e, "spheres":
/// [{"origin": [x, y, z], "radius": r}, ...]}, as foam's generate_spheres.py writes it.
/// A robot: foam's sphere database, {"<link>": {"<branch>": {"<depth>": level}}}, as its
/// SpherizationHelper caches per link and collision mesh (foam keys it "link::mesh file").
///
/// medspheres writes one level per set (depth "1", branch = the number of spheres), with
/// mean, best and worst null: they are spheretree's own error measures, which medspheres
/// does not compute. Readers take the last level of a mesh file (or the chosen one); in a
/// database, per key the largest branch and then the largest depth, and keys "link::..."
/// of one link are joined. Numbers are written in their shortest exact form.

#include <optional>
#include <string>
#include <vector>

#include "medspheres/formats/robot_spheres.h"

namespace medspheres::formats {

struct FoamLevel {
  std::optional<double> mean, best, worst;  ///< foam's errors; null when absent
  std::vector<Sphere> spheres;
};

/// The one-mesh JSON text: one level holding \p spheres.
/// \throws InputError for invalid spheres.
std::string foam_mesh_json(const std::vector<Sphere>& spheres);

/// The levels of a one-mesh file. \throws InputError naming \p source, the level and the
///   sphere: not JSON, not a list of levels, a malformed sphere.
std::vector<FoamLevel> parse_foam_mesh_json(const std::string& text, const std::string& source);

/// The robot JSON text (foam's database layout).
std::string foam_robot_json(const RobotSpheres& spheres);

/// The spheres per link of a database file, in its order.
RobotSpheres parse_foam_robot_json(const std::string& text, const std::string& source);

/// True when \p text is a JSON object (a database) rather than a list (one mesh); false
/// for anything else, including text that is not JSON.
bool is_foam_robot_json(const std::string& text);

}  // namespace medspheres::formats
