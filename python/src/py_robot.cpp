// bake_robot: the robot command (every link of a URDF through the bake pipeline) and the
// files it writes; evaluate_robot: eval of a robot-level sphere file.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "medspheres/formats/robot_outputs.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/measure/evaluate_set.h"
#include "medspheres/number_text.h"
#include "medspheres/options/bake_flags.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/evaluate_set_robot.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_bake/robot_planner_setup.h"
#include "medspheres/robot_bake/robot_warnings.h"
#include "medspheres/robot_file.h"
#include "medspheres/thread_option.h"
#include "py_common.h"

namespace medspheres::python {

namespace {

// What bake_robot returns: the baked model (per-link inner and outer sets, the planner
// setup for the set chosen) and its rows; the solids and request to set up another set.
struct RobotBake {
  RobotBakeResult result;
  std::string urdf;
  std::vector<std::string> inputs;  // the files read: an output folder must hold none
  std::vector<LinkSolid> solids;
  PlannerRequest planner;
  formats::SphereChoice choice = formats::SphereChoice::kOuter;  // of result.model.planner
  SelfCollisionRun run;                                          // of result.model.planner
};

// The model's planner setup made for \p choice, when it was made for another.
void plan_for(RobotBake& b, formats::SphereChoice choice) {
  if (b.result.model.planner && b.choice == choice) return;
  b.result.model.planner = make_planner_setup(b.result.model, b.solids, choice, b.planner, &b.run);
  b.choice = choice;
}

py::dict stats_dict(const LinkBakeStats& s) {
  py::dict d;
  d["link"] = s.link;
  d["parts"] = s.parts;
  d["primitive_spheres"] = s.primitive_spheres;
  d["triangles"] = s.triangles;
  d["budget"] = s.budget ? py::cast(*s.budget) : py::none();
  d["spheres"] = s.spheres;
  d["outer_spheres"] = s.outer_spheres;
  d["outer_certified"] = s.outer_certified;
  d["outer_protrusion"] = s.outer_protrusion;
  d["nerr"] = s.nerr;
  d["nerr_kind"] = s.nerr_kind;
  d["seconds"] = s.seconds;
  d["baked_as"] = s.baked_as;
  d["note"] = s.note;
  d["inner_filled"] = s.inner_filled;
  d["outer_filled"] = s.outer_filled;
  return d;
}

void write_outputs(RobotBake& b, const std::string& out, const std::vector<std::string>& names,
                   const std::string& set) {
  const std::vector<formats::SphereFormat> chosen = formats::robot_output_formats(names);
  const std::optional<formats::SphereChoice> choice = formats::parse_set_choice(set);
  formats::check_output_dir(out);
  check_output_spares_inputs(out, b.inputs);
  py::gil_scoped_release release;
  const formats::SphereChoice c = formats::robot_output_choice(choice, b.result.model);
  plan_for(b, c);
  formats::write_robot_outputs(out, chosen, b.result.model, c, b.urdf);
}

struct RobotArgs {
  std::optional<std::string> output;
  std::vector<std::string> formats;
  std::string set;
  std::map<std::string, std::string> packages;
  bool from_visual;
  RobotBudgetFlags budget;
  int jobs;
  std::optional<int> resolution;
  BakeFlags flags;
  bool measure, outer;
  bool fill = false;         // thin-shelled links' inner sets on their filled solid
  bool fill_covers = false;  // and their covering sets
  CoverSearch cover_search;  // of the covering sets
  std::map<std::string, std::vector<Sphere>> cover_start;
  PlannerRequest planner;
};

// cover_start of bake_robot: None, a per-link sphere file's path, or {link: spheres}
// (a SphereSet or an n x 4 array each).
std::map<std::string, std::vector<Sphere>> link_spheres_arg(const py::object& arg) {
  if (arg.is_none()) return {};
  if (is_path(arg)) return formats::read_link_sphere_map(path_of(arg), "cover_start");
  std::map<std::string, std::vector<Sphere>> out;
  for (const auto& [key, value] : arg.cast<py::dict>()) {
    const std::string link = key.cast<std::string>();
    out[link] = sphere_set_of(value, "cover_start['" + link + "']").spheres;
  }
  return out;
}

RobotBake bake_robot_py(const std::string& urdf, const RobotArgs& a) {
  check_threads_option(a.jobs, "jobs");  // by its name here, before it sizes the matrix too
  RobotBakeOptions options;
  BakeFlags flags = a.flags;
  if (a.resolution) flags.resolution = *a.resolution;
  options.request = bake_request(flags);
  options.request.measure = a.measure;
  set_robot_cover_search(a.cover_search, a.outer, !a.cover_start.empty(), options.request,
                         "outer=False");
  options.budget = robot_budget(a.budget, options.request, a.resolution.has_value());
  options.jobs = a.jobs;
  options.outer = a.outer;
  options.fill_thin_shells = a.fill;
  options.fill_thin_shell_covers = a.fill_covers;
  options.outer_start = a.cover_start;
  validate(a.planner.self_collision);
  const std::optional<formats::SphereChoice> set = formats::parse_set_choice(a.set);
  if (a.output) {
    formats::robot_output_formats(a.formats);
    formats::check_output_dir(*a.output);
  }
  UrdfReadOptions read;
  for (const auto& [package, dir] : a.packages) add_package_dir(read.packages, package + "=" + dir);
  read.from_visual = a.from_visual;
  RobotBake out;
  std::vector<std::string> warnings;
  out.urdf = urdf;
  out.planner = a.planner;
  out.planner.self_collision.threads = a.jobs;
  {
    py::gil_scoped_release release;
    const UrdfRobot robot = read_urdf(urdf, read);
    out.inputs = robot_input_files(robot);
    out.inputs.push_back(out.planner.srdf);
    if (a.output) check_output_spares_inputs(*a.output, out.inputs);
    check_planner_request(robot.model, out.planner);
    warnings = robot_warnings(robot, read.from_visual);
    out.solids = load_link_solids(robot);
    out.result = bake_robot(robot, out.solids, options);
    plan_for(out, formats::robot_output_choice(set, out.result.model));
  }
  if (!out.result.unused_outer_start.empty()) {
    std::string links;
    for (const std::string& l : out.result.unused_outer_start) links += " " + l;
    warn_all({count_text(out.result.unused_outer_start.size(), "link") +
              " of cover_start with no meshed part in the robot, not used:" + links},
             urdf);
  }
  warn_all(warnings, urdf);
  if (a.output) write_outputs(out, *a.output, a.formats, a.set);
  return out;
}

py::object evaluate_robot_py(const py::object& urdf, const py::handle& spheres, long long samples,
                             long long surface_samples, std::uint64_t seed, int threads,
                             const std::map<std::string, std::string>& packages) {
  const FitOptions options = fit_options(samples, surface_samples, seed, threads);
  UrdfReadOptions read;
  for (const auto& [package, dir] : packages) add_package_dir(read.packages, package + "=" + dir);
  const std::string urdf_path = path_of(urdf);
  std::string json;
  if (is_path(spheres)) {
    const std::string file = path_of(spheres);
    py::gil_scoped_release release;
    json = robot_evaluation_json(evaluate_robot_file(urdf_path, read, file, options));
  } else {
    const std::map<std::string, SphereSet> sets = link_spheres_of(spheres, "spheres");
    py::gil_scoped_release release;
    json = robot_evaluation_json(evaluate_robot_spheres(urdf_path, read, sets, "spheres", options));
  }
  const py::object result = json_loads(json);
  std::vector<std::string> unknown;
  for (const py::handle link : result["unknown_links"])
    unknown.push_back("link '" + link.cast<std::string>() + "' is not in the robot, not measured");
  warn_all(unknown, is_path(spheres) ? path_of(spheres) : "spheres");
  return result["links"];
}

// RobotBake: what bake_robot returns.
void register_robot_bake(py::module_& m) {
  py::class_<RobotBake>(m, "RobotBake", "A baked robot: every link's inner and outer sets.")
      .def_property_readonly(
          "links",
          [](const RobotBake& b) {
            py::dict out;
            for (const Link& l : b.result.model.links) {
              py::dict sets;
              sets["inner"] = spheres_array(l.spheres.inner.spheres);
              sets["outer"] = spheres_array(l.spheres.outer.spheres);
              out[py::str(l.name)] = sets;
            }
            return out;
          },
          "Link name -> {'inner': n x 4, 'outer': k x 4} float64 arrays (x, y, z, r) in the "
          "link's frame, metres; in the URDF's link order.")
      .def_property_readonly(
          "stats",
          [](const RobotBake& b) {
            py::list rows;
            for (const LinkBakeStats& s : b.result.links) rows.append(stats_dict(s));
            return rows;
          },
          "One dict per link (the rows of the robot command's summary).")
      .def_property_readonly("seconds", [](const RobotBake& b) { return b.result.seconds; })
      .def_property_readonly("name", [](const RobotBake& b) { return b.result.model.name; })
      .def_property_readonly(
          "planner",
          [](const RobotBake& b) {
            const py::object file = json_loads(robot_to_json(b.result.model));
            return py::object(file["planner"]);
          },
          "The planner setup the files carry, as the robot file's \"planner\" object: "
          "tool_frames (and tool_frames_from), locked_joints, default_positions (and "
          "default_from), self_collision: samples, seed, threshold, margin, srdf, buffer "
          "{link: metres}, pairs [[link1, link2, class, skipped(, reason)]] (docs/"
          "self-collision.md).")
      .def_property_readonly(
          "self_collision_estimate",
          [](const RobotBake& b) -> py::object {
            const SelfCollisionEstimate& e = b.run.estimate;
            if (e.samples == 0) return py::none();
            py::dict d;
            d["samples"] = e.samples;
            d["seed"] = e.seed;
            d["false_positives"] = e.false_positives;
            d["false_negatives"] = e.false_negatives;
            py::list alone;
            for (const auto& [pair, n] : e.alone)
              alone.append(py::make_tuple(pair.first, pair.second, n));
            d["alone"] = alone;
            return py::object(std::move(d));
          },
          "The files' self-collision checks against the meshes over other random "
          "configurations (the robot command's \"self-collision estimate\" line; None without "
          "the matrix, when it checks no pair, or with self_collision_estimate=0): samples, "
          "seed, false_positives (a checked pair's spheres touch, no two links' meshes do), "
          "false_negatives (a "
          "checked pair's meshes touch, no checked pair's spheres do), alone [(link1, link2, "
          "configurations)] (the pairs whose spheres alone make false positives, most first).")
      .def(
          "to_json", [](const RobotBake& b) { return robot_to_json(b.result.model); },
          "The medspheres robot file's JSON text.")
      .def(
          "save",
          [](RobotBake& b, const py::object& output, const std::vector<std::string>& formats,
             const std::string& set) { write_outputs(b, path_of(output), formats, set); },
          py::arg("output"), py::arg("formats") = std::vector<std::string>{},
          py::arg("set") = "auto",
          "Writes the robot command's files into the folder `output` (replaced as a whole): "
          "`formats` among robot, curobo, xrdf, urdf, srdf, foam, sph (default: all); `set` "
          "the set the planner formats carry: 'auto' (outer when baked), 'inner', 'outer'.");
}

}  // namespace

void register_robot(py::module_& m) {
  register_robot_bake(m);
  const BakeOptions d;
  m.def(
      "bake_robot",
      [](const py::object& urdf, const py::object& output, const std::vector<std::string>& formats,
         const std::string& set, const std::map<std::string, std::string>& packages,
         bool from_visual, std::optional<long long> spheres_per_link,
         std::optional<long long> budget, const std::map<std::string, long long>& links, int jobs,
         std::optional<int> resolution, double object_angle, std::optional<double> target_error,
         bool dilate, const py::object& vertex_tolerance, const py::object& max_protrusion,
         const py::object& cover, std::uint64_t seed, const std::string& solid,
         int robust_resolution, const py::object& robust_thickness, bool measure, bool outer,
         const py::object& cover_start, bool fill, bool fill_covers, double protrusion_allowance,
         int protrusion_restarts, int balance_rounds, const std::vector<std::string>& tool_frames,
         const std::vector<std::string>& free_joints, const py::object& srdf, bool self_collision,
         std::size_t self_collision_samples, unsigned self_collision_seed,
         double self_collision_threshold, double self_collision_margin,
         std::size_t self_collision_estimate) {
        RobotArgs a;
        if (!output.is_none()) a.output = path_of(output);
        a.formats = formats;
        a.set = set;
        a.packages = packages;
        a.from_visual = from_visual;
        a.budget.spheres_per_link = spheres_per_link;
        a.budget.budget = budget;
        for (const auto& [link, k] : links) a.budget.links.emplace_back(link, k);
        a.jobs = jobs;
        a.resolution = resolution;
        a.flags.object_angle = object_angle;
        a.flags.target_error = target_error;
        a.flags.dilation = {dilate, length_text(vertex_tolerance, "vertex_tolerance"),
                            length_text(max_protrusion, "max_protrusion"),
                            length_text(cover, "cover"), seed};
        a.flags.solid = {solid, robust_resolution,
                         length_text(robust_thickness, "robust_thickness")};
        a.measure = measure;
        a.outer = outer;
        a.cover_start = link_spheres_arg(cover_start);
        a.fill = fill;
        a.fill_covers = fill_covers;
        a.cover_search = {protrusion_allowance, protrusion_restarts, balance_rounds};
        a.planner.tool_frames = tool_frames;
        a.planner.free_joints = free_joints;
        if (!srdf.is_none()) a.planner.srdf = path_of(srdf);
        a.planner.sample = self_collision;
        a.planner.self_collision.samples = self_collision_samples;
        a.planner.self_collision.seed = self_collision_seed;
        a.planner.self_collision.threshold = self_collision_threshold;
        a.planner.self_collision.margin = self_collision_margin;
        a.planner.self_collision.estimate = self_collision_estimate;
        return bake_robot_py(path_of(urdf), a);
      },
      py::arg("urdf"), py::arg("output") = py::none(), py::kw_only(),
      py::arg("formats") = std::vector<std::string>{}, py::arg("set") = "auto",
      py::arg("packages") = std::map<std::string, std::string>{}, py::arg("from_visual") = false,
      py::arg("spheres_per_link") = py::none(), py::arg("budget") = py::none(),
      py::arg("links") = std::map<std::string, long long>{}, py::arg("jobs") = 0,
      py::arg("resolution") = py::none(), py::arg("object_angle") = d.object_angle,
      py::arg("target_error") = py::none(), py::arg("dilate") = false,
      py::arg("vertex_tolerance") = py::none(), py::arg("max_protrusion") = py::none(),
      py::arg("cover") = py::none(), py::arg("seed") = BakeRequest{}.seed,
      py::arg("solid") = "auto", py::arg("robust_resolution") = RobustSolidOptions{}.resolution,
      py::arg("robust_thickness") = py::none(), py::arg("measure") = true, py::arg("outer") = true,
      py::arg("cover_start") = py::none(), py::arg("fill") = false, py::arg("fill_covers") = false,
      py::arg("protrusion_allowance") = CoverSearch{}.protrusion_allowance,
      py::arg("protrusion_restarts") = CoverSearch{}.protrusion_restarts,
      py::arg("balance_rounds") = CoverSearch{}.balance_rounds,
      py::arg("tool_frames") = std::vector<std::string>{},
      py::arg("free_joints") = std::vector<std::string>{}, py::arg("srdf") = py::none(),
      py::arg("self_collision") = true,
      py::arg("self_collision_samples") = SelfCollisionOptions{}.samples,
      py::arg("self_collision_seed") = SelfCollisionOptions{}.seed,
      py::arg("self_collision_threshold") = SelfCollisionOptions{}.threshold,
      py::arg("self_collision_margin") = SelfCollisionOptions{}.margin,
      py::arg("self_collision_estimate") = SelfCollisionOptions{}.estimate,
      "Bakes every link of a URDF robot, as `medspheres robot URDF -o OUTPUT` does, and "
      "returns a RobotBake (per-link arrays, stats); with `output`, also writes the "
      "planners' files there (see RobotBake.save).\n\n"
      "packages: {'pkg': '/dir'} for package:// URIs. Budgets: spheres_per_link (default 32 "
      "unless budget, target_error or resolution is given), budget (the whole robot, shared "
      "by surface area), links ({'link': K}). outer: also bake a certified covering set per "
      "link. cover_start: a per-link sphere file's path (cuRobo, XRDF, ...) or {'link': "
      "spheres} in link frames, a planner's own set: each such link's covering set is made "
      "from it (tighten_cover) instead of baked; links with no meshed part are named in a "
      "UserWarning. fill: a thin-shelled link's inner set on its filled solid (--fill; its "
      "stats row says inner_filled). fill_covers: a thin-shelled link's covering set baked on "
      "its filled solid and certified on its real surface (--fill-covers). protrusion_allowance, "
      "protrusion_restarts, balance_rounds: the covering sets' search, as --protrusion-allowance, "
      "--protrusion-restarts and --balance-rounds (docs/covers.md). measure=False skips the "
      "exact volume error. tool_frames, free_joints (finger joints left free that the "
      "rules would lock), srdf and the self_collision options: the planner files, as the "
      "robot command's --tool-frame, --free-joint, --srdf and --self-collision-*. solid, "
      "robust_resolution, "
      "robust_thickness: each link's solid, as in bake. Lengths (vertex_tolerance, "
      "max_protrusion, cover, robust_thickness) are numbers in metres (the URDF's unit, in "
      "each link's scaled mesh) or text: '0.01' or '0.003L' (a multiple of the largest side "
      "of each link's box). The GIL is released while baking.");

  def_evaluation(
      m, "evaluate_robot", &evaluate_robot_py, "urdf",
      py::arg("packages") = std::map<std::string, std::string>{},
      "Each link's spheres against that link's solid in its frame, as `medspheres eval "
      "ROBOT.urdf SPHERES --json` reports it: a list of dicts, one per link of the URDF in "
      "its order (link, spheres, primitives, note and, where measured, nerr, nerr_kind, "
      "max_protrusion, mc_error, uncovered_max, uncovered_mean, surface_certificate, "
      "warnings).\n\n"
      "spheres: a robot-level sphere file (robot, cuRobo YAML, XRDF, spherized URDF, SRDF, "
      "foam's per-link JSON) or a dict link name -> spheres (a SphereSet or an n x 4 array, "
      "link frame, metres), such as {k: v['outer'] for k, v in RobotBake.links.items()}.\n"
      "A sphere equal to one of the link's sphere primitives is exact and counted in "
      "'primitives'; the others are measured against the link's meshed parts. packages: "
      "{'pkg': '/dir'} for package:// URIs. The GIL is released while measuring.");
}

}  // namespace medspheres::python
