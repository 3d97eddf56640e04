// medspheres eval ROBOT.urdf SPHERES: each link's solid in its frame against its spheres.
#include "cmd_eval_robot.h"

#include <algorithm>
#include <cctype>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "medspheres/bake/robot_bake.h"
#include "medspheres/error.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_file.h"

namespace medspheres::cli {

namespace {

// The spheres of every link in a robot-level sphere file (any format convert reads): a
// robot file gives each link's inner set, or its outer set where it has no inner one.
std::map<std::string, SphereSet> robot_spheres(const std::string& path) {
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
  j["warnings"] = r.warnings;
  return j;
}

std::string cell(const std::string& text, std::size_t width) {
  return text.size() >= width ? text + " " : text + std::string(width - text.size(), ' ');
}

void print_text(const RobotEvalArgs& args, const std::vector<LinkFit>& fits) {
  std::size_t width = 4;
  for (const LinkFit& f : fits) width = std::max(width, f.link.size() + 2);
  std::cout << "eval " << args.spheres << " against " << args.urdf << " (link frames)\n"
            << cell("link", width) << cell("spheres", 9) << cell("nerr", 24) << cell("mc error", 11)
            << cell("protrusion", 12) << cell("uncovered", 11) << "note\n";
  for (const LinkFit& f : fits) {
    std::cout << cell(f.link, width) << cell(std::to_string(f.spheres), 9);
    if (f.fit) {
      const FitReport& r = *f.fit;
      const std::string kind = to_string(r.volume.kind);
      std::cout << cell(number_text(r.volume.nerr, 4) + (kind == "exact" ? "" : " (" + kind + ")"),
                        24)
                << cell(number_text(r.monte_carlo.error.estimate, 4), 11)
                << cell(number_text(r.volume.max_protrusion, 3), 12)
                << cell(number_text(r.coverage.max, 3), 11);
    } else {
      std::cout << cell("-", 24) << cell("-", 11) << cell("-", 12) << cell("-", 11);
    }
    std::string note = f.note;
    if (f.primitives > 0)
      note += (note.empty() ? "" : "; ") + std::to_string(f.primitives) + " exact primitive(s)";
    std::cout << note << "\n";
  }
}

}  // namespace

std::map<std::string, SphereSet> read_robot_spheres(const std::string& path) {
  return robot_spheres(path);
}

bool is_robot_description(const std::string& path) {
  if (path.size() < 5) return false;
  std::string ext = path.substr(path.size() - 5);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".urdf";
}

int run_eval_robot(const RobotEvalArgs& args) {
  UrdfReadOptions read;
  for (const std::string& p : args.packages) add_package_dir(read.packages, p);
  const std::map<std::string, SphereSet> spheres = robot_spheres(args.spheres);
  const UrdfRobot robot = read_urdf(args.urdf, read);
  const std::vector<LinkFit> fits =
      evaluate_robot_fit(load_link_solids(robot), spheres, args.spheres, args.fit);
  if (args.json) {
    nlohmann::ordered_json j = {{"urdf", args.urdf}, {"spheres_file", args.spheres}};
    j["links"] = nlohmann::ordered_json::array();
    for (const LinkFit& f : fits) j["links"].push_back(fit_json(f));
    std::cout << j.dump(2) << "\n";
  } else {
    print_text(args, fits);
  }
  return kExitOk;
}

}  // namespace medspheres::cli
