#include "medspheres/robot_bake/evaluate_set_robot.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/mesh/cover_certificate_json.h"
#include "medspheres/number_text.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot_file.h"

namespace medspheres {

namespace {

nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json fit_json(const LinkFit& f) {
  nlohmann::ordered_json j = {
      {"link", f.link}, {"spheres", f.spheres}, {"primitives", f.primitives}, {"note", f.note}};
  if (!f.fit) return j;
  const FitReport& r = *f.fit;
  j["nerr"] = number(r.volume.nerr);
  j["nerr_kind"] = to_string(r.volume.kind);
  j["max_protrusion"] = r.volume.max_protrusion;
  j["mc_error"] = number(r.monte_carlo.error.estimate);
  j["uncovered_max"] = r.coverage.max;
  j["uncovered_mean"] = r.coverage.mean;
  if (f.certificate)
    j["surface_certificate"] =
        nlohmann::ordered_json::parse(cover_certificate_json(*f.certificate));
  j["warnings"] = r.warnings;
  return j;
}

}  // namespace

std::map<std::string, SphereSet> read_robot_spheres(const std::string& path) {
  std::map<std::string, SphereSet> out;
  const bool robot_file =
      path.size() >= 11 && path.compare(path.size() - 11, 11, ".robot.json") == 0;
  if (robot_file) {
    for (const Link& link : load_robot(path).links)
      out[link.name] = link.spheres.inner.empty() ? link.spheres.outer : link.spheres.inner;
    return out;
  }
  formats::ReadOptions options;
  options.choice = formats::SphereChoice::kInner;  // a robot file named .json
  const formats::SphereDocument doc = formats::read_sphere_document(path, std::nullopt, options);
  if (doc.set)
    throw InputError(path,
                     "holds one sphere set, not a robot's (give a robot-level file: robot, "
                     "cuRobo, XRDF, spherized URDF, SRDF or foam's per-link JSON)");
  for (const formats::LinkSphereList& link : doc.links) out[link.link].spheres = link.spheres;
  return out;
}

RobotEvaluation evaluate_robot_spheres(const std::string& urdf, const UrdfReadOptions& read,
                                       const std::map<std::string, SphereSet>& spheres,
                                       const std::string& spheres_file, const FitOptions& options) {
  RobotEvaluation out;
  out.urdf = urdf;
  out.spheres_file = spheres_file;
  const UrdfRobot robot = read_urdf(urdf, read);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  std::map<std::string, SphereSet> known;
  for (const auto& entry : spheres) {
    const std::string& link = entry.first;
    if (std::any_of(solids.begin(), solids.end(),
                    [&](const LinkSolid& s) { return s.link == link; }))
      known.emplace(link, entry.second);
    else
      out.unknown_links.push_back(link);
  }
  if (known.empty() && !out.unknown_links.empty())
    throw InputError(spheres_file, "none of its " + count_text(out.unknown_links.size(), "link") +
                                       " is a link of the robot in " + urdf + " (first: '" +
                                       out.unknown_links.front() + "')");
  out.links = evaluate_robot_fit(solids, known, spheres_file, options);
  return out;
}

RobotEvaluation evaluate_robot_file(const std::string& urdf, const UrdfReadOptions& read,
                                    const std::string& spheres_file, const FitOptions& options) {
  return evaluate_robot_spheres(urdf, read, read_robot_spheres(spheres_file), spheres_file,
                                options);
}

std::string robot_evaluation_json(const RobotEvaluation& evaluation) {
  nlohmann::ordered_json j = {{"urdf", evaluation.urdf}, {"spheres_file", evaluation.spheres_file}};
  j["links"] = nlohmann::ordered_json::array();
  for (const LinkFit& f : evaluation.links) j["links"].push_back(fit_json(f));
  j["unknown_links"] = evaluation.unknown_links;
  return j.dump(2);
}

}  // namespace medspheres
