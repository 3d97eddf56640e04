// medspheres eval ROBOT.urdf SPHERES: each link's solid in its frame against its spheres.
#include "cmd_eval_robot.h"

#include <algorithm>
#include <cctype>
#include <iostream>

#include "cli_common.h"
#include "medspheres/robot/package_path.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/robot_bake.h"

namespace medspheres::cli {

namespace {

std::string cell(const std::string& text, std::size_t width) {
  return text.size() >= width ? text + " " : text + std::string(width - text.size(), ' ');
}

void print_text(const RobotEvalArgs& args, const std::vector<LinkFit>& fits) {
  std::size_t width = 4;
  for (const LinkFit& f : fits) width = std::max(width, f.link.size() + 2);
  std::cout << "eval " << args.spheres << " against " << args.urdf << " (link frames)\n"
            << cell("link", width) << cell("spheres", 9) << cell("nerr", 24) << cell("mc error", 11)
            << cell("protrusion", 12) << cell("uncovered", 11) << cell("surface", 10) << "note\n";
  for (const LinkFit& f : fits) {
    std::cout << cell(f.link, width) << cell(std::to_string(f.spheres), 9);
    if (f.fit) {
      const FitReport& r = *f.fit;
      const std::string kind = to_string(r.volume.kind);
      std::cout << cell(number_text(r.volume.nerr, 4) + (kind == "exact" ? "" : " (" + kind + ")"),
                        24)
                << cell(number_text(r.monte_carlo.error.estimate, 4), 11)
                << cell(number_text(r.volume.max_protrusion, 3), 12)
                << cell(number_text(r.coverage.max, 3), 11)
                << cell(f.certificate->certified ? "certified" : "NOT", 10);
    } else {
      std::cout << cell("-", 24) << cell("-", 11) << cell("-", 12) << cell("-", 11)
                << cell("-", 10);
    }
    std::string note = f.note;
    if (f.primitives > 0)
      note += (note.empty() ? "" : "; ") + count_text(f.primitives, "exact primitive");
    std::cout << note << "\n";
  }
}

}  // namespace

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
  const RobotEvaluation e = evaluate_robot_file(args.urdf, read, args.spheres, args.fit);
  if (!e.unknown_links.empty()) {
    std::cerr << "medspheres: warning: " << args.spheres << ": "
              << count_text(e.unknown_links.size(), "link") << " not in " << args.urdf
              << ", not measured:";
    for (const std::string& link : e.unknown_links) std::cerr << " " << link;
    std::cerr << "\n";
  }
  if (args.json)
    std::cout << robot_evaluation_json(e) << "\n";
  else
    print_text(args, e.links);
  return kExitOk;
}

}  // namespace medspheres::cli
