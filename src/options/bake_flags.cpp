#include "medspheres/options/bake_flags.h"

#include "medspheres/error.h"
#include "medspheres/number_text.h"
#include "medspheres/options/option_text.h"

namespace medspheres {

std::optional<Length> length_option(const std::optional<std::string>& text, const char* field) {
  if (!text) return std::nullopt;
  try {
    return parse_length(*text);
  } catch (const InputError& e) {
    throw e.with_field(field);
  }
}

void set_dilation(const DilationFlags& flags, BakeRequest& request) {
  request.dilate = flags.dilate;
  request.vertex_tolerance = length_option(flags.vertex_tolerance, "vertex_tolerance");
  request.max_protrusion = length_option(flags.max_protrusion, "max_protrusion");
  request.cover = length_option(flags.cover, "cover");
  request.seed = flags.seed;
}

namespace {

// The solid \p flags name, parsed but not checked.
SolidRequest parse_solid(const SolidFlags& flags) {
  SolidRequest s;
  s.kind = parse_solid_kind(flags.solid);
  s.robust.resolution = flags.robust_resolution;
  s.robust_thickness = length_option(flags.robust_thickness, "robust_thickness");
  return s;
}

}  // namespace

void set_solid(const SolidFlags& flags, BakeRequest& request) {
  const SolidRequest s = parse_solid(flags);
  request.solid = s.kind;
  request.robust.resolution = s.robust.resolution;  // the request keeps its escalation
  request.robust_thickness = s.robust_thickness;
}

SolidRequest solid_request(const SolidFlags& flags) {
  SolidRequest s = parse_solid(flags);
  check_solid_request(s);
  return s;
}

namespace {

std::size_t count_option(long long v, const char* field) {
  if (v < 1)
    throw InputError::option(ErrorKind::kOutOfRange, field, std::to_string(v),
                             "must be >= 1, got " + std::to_string(v));
  return static_cast<std::size_t>(v);
}

}  // namespace

RobotBudget robot_budget(const RobotBudgetFlags& f, const BakeRequest& request,
                         bool resolution_given) {
  RobotBudget b;
  if (f.spheres_per_link) b.per_link = count_option(*f.spheres_per_link, "spheres_per_link");
  if (!f.spheres_per_link && !f.budget && !request.target_error && !resolution_given)
    b.per_link = kDefaultSpheresPerLink;
  if (f.budget) b.total = count_option(*f.budget, "budget");
  for (const auto& [link, k] : f.links) b.links[link] = count_option(k, "link");
  return b;
}

void check_cover_search_unused(const CoverSearch& search, const std::string& problem,
                               std::vector<std::string> related) {
  const CoverSearch d;
  std::string field, value;
  if (search.protrusion_allowance != d.protrusion_allowance)
    field = "protrusion_allowance", value = number_text(search.protrusion_allowance);
  else if (search.protrusion_restarts != d.protrusion_restarts)
    field = "protrusion_restarts", value = std::to_string(search.protrusion_restarts);
  else if (search.balance_rounds != d.balance_rounds)
    field = "balance_rounds", value = std::to_string(search.balance_rounds);
  else
    return;
  throw InputError::option(ErrorKind::kConflict, field, value,
                           "sets the search of a covering set baked to a budget, but " + problem,
                           {}, std::move(related));
}

void set_robot_cover_search(const CoverSearch& search, bool outer, bool cover_start,
                            BakeRequest& request, const std::string& no_outer) {
  if (!outer)
    check_cover_search_unused(search, no_outer + " leaves the covering sets out", {no_outer});
  if (cover_start)
    check_cover_search_unused(search, "cover_start tightens its spheres instead", {"cover_start"});
  validate(search);
  request.cover_search = search;
}

BakeRequest bake_request(const BakeFlags& f) {
  if (f.method != "medial" && f.method != "cover")
    throw InputError::option(ErrorKind::kOutOfRange, "method", f.method,
                             "must be medial or cover, got '" + f.method + "'");
  BakeRequest r;
  r.medial.resolution = f.resolution;
  r.medial.object_angle = f.object_angle;
  r.medial.medial_tolerance = f.medial_tolerance;
  r.medial.threads = f.threads;
  r.method = f.method == "cover" ? BakeMethod::kCover : BakeMethod::kMedial;
  if (f.max_spheres) {
    // A negative budget has no size_t; it is out of range as 0 is.
    if (*f.max_spheres < 0)
      throw InputError::option(ErrorKind::kOutOfRange, "max_spheres",
                               std::to_string(*f.max_spheres),
                               "must be >= 1, got " + std::to_string(*f.max_spheres));
    r.max_spheres = static_cast<std::size_t>(*f.max_spheres);
  }
  r.target_error = f.target_error;
  r.cover_start = f.cover_start;
  if (f.method != "cover")
    check_cover_search_unused(f.cover_search, "method is " + f.method, {"method"});
  if (!f.cover_start.empty())
    check_cover_search_unused(f.cover_search, "cover_start tightens a given set instead",
                              {"cover_start"});
  r.cover_search = f.cover_search;
  set_dilation(f.dilation, r);
  set_solid(f.solid, r);
  validate(r);
  return r;
}

}  // namespace medspheres
