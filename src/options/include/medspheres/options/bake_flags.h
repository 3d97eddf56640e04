#pragma once
/// \file
/// The bake, solid and robot budget options as a user gives them (the CLI's flags, the
/// Python module's keywords), turned into the library's typed requests (BakeRequest,
/// SolidRequest, RobotBudget): one place for every tool that bakes or evaluates.
///
/// Errors: InputError named by the library's fields ("max_spheres", "vertex_tolerance",
/// "method"), which the CLI prints as its flags and Python as its keywords.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/measure/solid_choice.h"
#include "medspheres/robot_bake/robot_bake.h"

namespace medspheres {

/// The length option \p text of the request field \p field, parsed (a number, or a
/// multiple of L written with an L); an error names the field.
std::optional<Length> length_option(const std::optional<std::string>& text, const char* field);

/// The dilation options (dilate, vertex_tolerance, max_protrusion, cover, seed).
struct DilationFlags {
  bool dilate = false;
  std::optional<std::string> vertex_tolerance, max_protrusion, cover;
  std::uint64_t seed = BakeRequest{}.seed;
};

/// Sets the request's dilation from \p flags (lengths parsed; ranges are validate()'s).
void set_dilation(const DilationFlags& flags, BakeRequest& request);

/// The solid options (solid, robust_resolution, robust_thickness).
struct SolidFlags {
  std::string solid = "auto";  ///< "auto", "winding" or "robust" (parse_solid_kind)
  int robust_resolution = RobustSolidOptions{}.resolution;
  std::optional<std::string> robust_thickness;  ///< a length, or a multiple of L
};

/// Sets the request's solid from \p flags (an unknown solid is an InputError; ranges are
/// validate()'s).
void set_solid(const SolidFlags& flags, BakeRequest& request);

/// The solid \p flags name, for `eval` (evaluate_set.h), checked (check_solid_request).
/// \throws InputError (kOutOfRange, field "solid" or "robust_thickness") for a solid that is
///   not auto, winding or robust, or a thickness that is no length, or negative.
SolidRequest solid_request(const SolidFlags& flags);

/// Everything `medspheres bake` accepts besides the mesh and the output.
struct BakeFlags {
  std::string method = "medial";  ///< "medial" or "cover"
  int resolution = BakeOptions{}.resolution;
  double object_angle = BakeOptions{}.object_angle;
  double medial_tolerance = 0.0;
  std::optional<long long> max_spheres;  ///< signed: a negative count is reported, not wrapped
  std::optional<double> target_error;
  DilationFlags dilation;
  SolidFlags solid;
  int threads = 0;
  std::vector<Sphere> cover_start;  ///< the spheres --cover-start names, read (BakeRequest)
  CoverSearch cover_search;         ///< method cover with max_spheres only
};

/// Unless \p search is the default: a conflict (InputError kConflict) naming its first field
/// that differs, because \p problem (what keeps the search from running: "the covering
/// sets are not baked", ...); \p related: the options that cause it.
void check_cover_search_unused(const CoverSearch& search, const std::string& problem,
                               std::vector<std::string> related);

/// The flags as a request, validated (validate()): nonsense is reported before any work.
/// \throws InputError (kOutOfRange: field "method" for a method other than medial or
///   cover, "max_spheres" for a count below 1; kConflict: a cover search (CoverSearch's
///   fields) for inner spheres or a cover_start; and as validate()).
BakeRequest bake_request(const BakeFlags& flags);

/// A robot bake's cover search into its \p request (whose method is medial: the search is
/// the covering sets'), unless it is the default and cannot run: a conflict naming its field
/// when no covering set is baked (\p outer false, the option that asks it named
/// \p no_outer: "no_outer" on the command line, "outer=False" in Python) or each is
/// tightened from given spheres (\p cover_start).
void set_robot_cover_search(const CoverSearch& search, bool outer, bool cover_start,
                            BakeRequest& request, const std::string& no_outer = "no_outer");

/// The budget options of a robot bake, as given (counts signed: below 1 is reported).
struct RobotBudgetFlags {
  std::optional<long long> spheres_per_link;
  std::optional<long long> budget;                       ///< the whole robot
  std::vector<std::pair<std::string, long long>> links;  ///< per link (link name, K)
};

/// The robot's budget: kDefaultSpheresPerLink per link when no budget is given and the
/// request has no error target and \p resolution_given is false (a resolution chosen by
/// hand bakes at that resolution).
/// \throws InputError (kOutOfRange: field "spheres_per_link", "budget" or "link") for a
///   count below 1.
RobotBudget robot_budget(const RobotBudgetFlags& flags, const BakeRequest& request,
                         bool resolution_given);

}  // namespace medspheres
