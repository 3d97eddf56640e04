// medspheres robot ROBOT.urdf -o OUTDIR: every link's spheres, in the planners' formats;
// several URDFs, folders or a list: a batch, each robot in its own folder under OUTDIR.
#include <algorithm>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "cmd_batch.h"
#include "medspheres/bake/bake_pipeline.h"
#include "medspheres/batch/batch_robot.h"
#include "medspheres/error.h"
#include "medspheres/formats/planner_options.h"
#include "medspheres/formats/robot_outputs.h"
#include "medspheres/formats/robot_spheres.h"
#include "medspheres/formats/self_collision_report.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/number_text.h"
#include "medspheres/options/bake_flags.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_file.h"
#include "medspheres/thread_option.h"
#include "solid_flags.h"

namespace medspheres::cli {

namespace {

struct RobotArgs {
  std::vector<std::string> urdfs;  ///< one URDF, or a batch's files and folders
  BatchFlags batch;
  std::string out;
  std::vector<std::string> formats;
  std::vector<std::string> packages;
  bool from_visual = false;
  std::optional<long long> spheres_per_link;
  std::optional<long long> budget;
  std::vector<std::string> link_budgets;
  int resolution = BakeOptions{}.resolution;
  double object_angle = BakeOptions{}.object_angle;
  std::optional<double> target_error;
  DilationFlags dilation;
  SolidFlags solid;
  bool no_measure = false;
  bool no_outer = false;
  bool fill = false;
  bool fill_covers = false;
  CoverSearch cover_search;
  std::string cover_start;  ///< a per-link sphere file the outer sets start from
  std::string set = "auto";
  std::vector<std::string> tool_frames;
  std::vector<std::string> free_joints;
  std::string srdf;
  bool no_self_collision = false;
  SelfCollisionOptions self_collision;
  bool contact = false;
  ContactOptions contact_options;
  bool resolution_given = false;
  bool quiet = false;
};

BakeRequest bake_request(const RobotArgs& a) {
  BakeRequest r;
  r.medial.resolution = a.resolution;
  r.medial.object_angle = a.object_angle;
  r.target_error = a.target_error;
  set_dilation(a.dilation, r);
  set_solid(a.solid, r);
  r.measure = !a.no_measure;
  set_robot_cover_search(a.cover_search, !a.no_outer, !a.cover_start.empty(), r);
  return r;
}

// --link NAME=K as (NAME, K); the counts are checked by the library.
RobotBudgetFlags budget_flags(const RobotArgs& a) {
  RobotBudgetFlags f{a.spheres_per_link, a.budget, {}};
  for (const std::string& text : a.link_budgets) {
    const std::size_t eq = text.rfind('=');  // link names may hold '=', counts do not
    long long k = 0;
    std::size_t used = 0;
    try {
      if (eq == std::string::npos || eq == 0) throw std::invalid_argument("no NAME=K");
      k = std::stoll(text.substr(eq + 1), &used);
    } catch (const std::exception&) {
      throw InputError("--link", "expected NAME=K with K a count, got '" + text + "'");
    }
    if (used != text.size() - eq - 1)
      throw InputError("--link", "expected NAME=K with K a count, got '" + text + "'");
    f.links.emplace_back(text.substr(0, eq), k);
  }
  return f;
}

std::string cell(const std::string& text, std::size_t width) {
  return text.size() >= width ? text + " " : text + std::string(width - text.size(), ' ');
}

std::string nerr_text(const LinkBakeStats& s) {
  if (s.nerr_kind.empty()) return "-";
  return number_text(s.nerr, 4) + (s.nerr_kind == "exact" ? "" : " (" + s.nerr_kind + ")");
}

void print_progress(const LinkBakeStats& s) {
  std::cerr << "  " << s.link << ": " << count_text(s.triangles, "triangle") << ", "
            << count_text(s.spheres, "sphere") << ", nerr " << nerr_text(s) << ", "
            << number_text(s.seconds, 3) << " s"
            << (s.baked_as.empty() ? "" : " (same bake as " + s.baked_as + ")")
            << (s.note.empty() ? "" : " (" + s.note + ")") << "\n";
}

void print_summary(const RobotBakeResult& r, const std::string& out) {
  std::size_t width = 4;
  for (const LinkBakeStats& s : r.links) width = std::max(width, s.link.size() + 2);
  std::cout << cell("link", width) << cell("triangles", 11) << cell("budget", 8)
            << cell("spheres", 9) << cell("nerr", 24) << cell("seconds", 9) << "note\n";
  std::size_t spheres = 0, triangles = 0;
  for (const LinkBakeStats& s : r.links) {
    spheres += s.spheres;
    triangles += s.triangles;
    std::string note = s.note;
    if (!s.baked_as.empty()) note += (note.empty() ? "" : "; ") + ("same bake as " + s.baked_as);
    if (s.outer_start > 0)
      note += (note.empty() ? "" : "; ") + ("covering set of " + std::to_string(s.outer_spheres) +
                                            " from " + std::to_string(s.outer_start) + " given");
    std::cout << cell(s.link, width) << cell(std::to_string(s.triangles), 11)
              << cell(s.budget ? std::to_string(*s.budget) : "-", 8)
              << cell(std::to_string(s.spheres), 9) << cell(nerr_text(s), 24)
              << cell(number_text(s.seconds, 3), 9) << note << "\n";
  }
  std::cout << cell("total", width) << cell(std::to_string(triangles), 11) << cell("", 8)
            << cell(std::to_string(spheres), 9) << cell("", 24)
            << cell(number_text(r.seconds, 3), 9) << "wall clock\n"
            << "wrote " << out << "\n";
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

// The matrix's estimate (self_collision_estimate.h): false positives, the pairs that make
// most of them alone, and false negatives.
void print_estimate(const SelfCollisionRun& run) {
  const SelfCollisionEstimate& e = run.estimate;
  if (e.samples == 0) return;
  std::cout << "self-collision estimate: of " << e.samples << " other random configurations (seed "
            << e.seed << "), " << e.false_positives << " ("
            << number_text(100.0 * double(e.false_positives) / double(e.samples), 3)
            << "%) have a checked pair's spheres touching while no two links' meshes do";
  if (!e.alone.empty()) {
    std::cout << " (by one pair alone:";
    for (std::size_t k = 0; k < e.alone.size() && k < 3; ++k)
      std::cout << (k ? ", " : " ") << e.alone[k].first.first << "-" << e.alone[k].first.second
                << " " << e.alone[k].second;
    std::cout << "; more spheres on such links, --link NAME=K, lower it)";
  }
  std::cout << ", and " << e.false_negatives
            << " have a checked pair's meshes touching while no checked pair's spheres do; "
            << number_text(run.estimate_seconds, 3) << " s\n";
}

// Where the tool frames and the default configuration came from, and the matrix's classes.
void print_planner_summary(const PlannerSetup& s, const SelfCollisionRun& run,
                           std::size_t sphere_pairs, const std::vector<std::string>& free_joints) {
  std::cout << "tool frames: " << joined(s.tool_frames) << " ("
            << tool_frames_from_text(s.tool_frames_from) << ")\n";
  if (!s.locked_joints.empty())
    std::cout << "locked joints (the gripper's): " << joined(s.locked_joints) << "\n";
  if (!free_joints.empty())
    std::cout << "free finger joints (--free-joint): " << joined(free_joints) << "\n";
  std::cout << "default configuration: " << default_from_text(s.default_from) << "\n";
  if (!s.self_collision || s.self_collision->samples == 0) return;
  std::cout << "self-collision matrix: " << s.self_collision->samples << " samples, "
            << number_text(run.seconds, 3) << " s, " << run.solids.mesh_queries
            << " exact mesh queries; pairs:";
  for (const auto& [kind, n] : formats::pair_class_counts(*s.self_collision))
    std::cout << " " << pair_class_name(kind) << " " << n.first;
  if (!run.contacts.empty())
    std::cout << "; " << count_text(run.contacts.size(), "pair")
              << " checked by a contact searched for";
  if (run.mirrored > 0)
    std::cout << "; " << count_text(run.mirrored, "pair") << " checked as "
              << (run.mirrored == 1 ? "its mirror image was" : "their mirror images were")
              << " seen colliding";
  std::cout << "; cuRobo checks " << count_text(sphere_pairs, "sphere pair");
  if (sphere_pairs > formats::kCuroboV1FastPairs)
    std::cout << " (more than the " << formats::kCuroboV1FastPairs
              << " that cuRobo v1's faster self-collision kernel takes; --spheres-per-link "
                 "lowers it)";
  std::cout << "\n";
  for (const auto& [a, b] : run.default_pairs)
    std::cout << "medspheres: warning: " << a << " and " << b
              << " touch at the default configuration\n";
  print_estimate(run);
}

// The options of the run as the robot file's provenance ("options" in its metadata): every
// flag that changes the spheres, as given (lengths as written, before L is resolved).
std::string options_json(const RobotArgs& a) {
  auto optional = [](const auto& v) {
    return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
  };
  nlohmann::ordered_json o;
  o["packages"] = a.packages;
  o["from_visual"] = a.from_visual;
  o["spheres_per_link"] = optional(a.spheres_per_link);
  o["budget"] = optional(a.budget);
  o["link"] = a.link_budgets;
  o["resolution"] = a.resolution_given ? nlohmann::ordered_json(a.resolution) : nullptr;
  o["object_angle"] = a.object_angle;
  o["target_error"] = optional(a.target_error);
  o["dilate"] = a.dilation.dilate;
  o["vertex_tolerance"] = optional(a.dilation.vertex_tolerance);
  o["max_protrusion"] = optional(a.dilation.max_protrusion);
  o["cover"] = optional(a.dilation.cover);
  o["seed"] = a.dilation.seed;
  o["solid"] = a.solid.solid;
  o["robust_resolution"] = a.solid.robust_resolution;
  o["robust_thickness"] = optional(a.solid.robust_thickness);
  o["measure"] = !a.no_measure;
  o["outer"] = !a.no_outer;
  o["fill"] = a.fill;
  o["fill_covers"] = a.fill_covers;
  o["protrusion_allowance"] = a.cover_search.protrusion_allowance;
  o["protrusion_restarts"] = a.cover_search.protrusion_restarts;
  o["balance_rounds"] = a.cover_search.balance_rounds;
  o["cover_start"] = a.cover_start.empty() ? nlohmann::ordered_json(nullptr)
                                           : nlohmann::ordered_json(a.cover_start);
  o["set"] = a.set;
  o["tool_frame"] = a.tool_frames;
  if (!a.free_joints.empty()) o["free_joint"] = a.free_joints;
  o["srdf"] = a.srdf.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(a.srdf);
  o["self_collision"] = !a.no_self_collision;
  o["self_collision_samples"] = a.self_collision.samples;
  o["self_collision_seed"] = a.self_collision.seed;
  o["self_collision_threshold"] = a.self_collision.threshold;
  o["self_collision_margin"] = a.self_collision.margin;
  o["contact"] = a.contact;
  if (a.contact) {
    o["contact_samples"] = a.contact_options.samples;
    o["contact_band"] = a.contact_options.band;
    o["contact_weight"] = a.contact_options.weight;
    o["contact_min_share"] = a.contact_options.min_share;
  }
  return o.dump();
}

// The spheres of --cover-start per link (a per-link file: cuRobo, XRDF, robot file, ...).
std::map<std::string, std::vector<Sphere>> start_spheres(const RobotArgs& a) {
  if (a.no_outer)
    throw InputError::option(ErrorKind::kConflict, "cover_start", a.cover_start,
                             "starts the outer sets, which --no-outer leaves out");
  return formats::read_link_sphere_map(a.cover_start, "cover_start");
}

// Everything the flags ask for, checked before any work.
RobotJob robot_job(const RobotArgs& a) {
  RobotJob job;
  job.bake.request = bake_request(a);
  job.bake.budget = robot_budget(budget_flags(a), job.bake.request, a.resolution_given);
  job.bake.jobs = a.batch.jobs;
  job.bake.outer = !a.no_outer;
  job.bake.fill_thin_shells = a.fill;
  if (a.fill_covers && a.no_outer)
    throw InputError::option(ErrorKind::kConflict, "fill_covers", "",
                             "fills the covering sets, which --no-outer leaves out");
  job.bake.fill_thin_shell_covers = a.fill_covers;
  check_threads_option(a.batch.jobs, "jobs");
  job.formats = formats::robot_output_formats(a.formats);
  job.set = formats::parse_set_choice(a.set);
  for (const std::string& p : a.packages) add_package_dir(job.read.packages, p);
  job.read.from_visual = a.from_visual;
  job.options_json = options_json(a);
  if (!a.cover_start.empty()) job.bake.outer_start = start_spheres(a);
  job.planner.tool_frames = a.tool_frames;
  job.planner.free_joints = a.free_joints;
  job.planner.srdf = a.srdf;
  job.planner.sample = !a.no_self_collision;
  job.planner.self_collision = a.self_collision;
  validate(job.planner.self_collision);
  ContactOptions contact = a.contact_options;
  contact.threads = a.batch.jobs;
  validate(contact);  // the values are checked with or without --contact
  if (a.contact) {
    if (a.no_self_collision || a.no_outer)
      throw InputError::option(ErrorKind::kConflict, "contact", "",
                               "needs the self-collision matrix and the outer sets "
                               "(drop --no-self-collision and --no-outer)");
    job.contact = contact;
  }
  return job;
}

// The batch of `robot`: URDFs through bake_robot_batch with \p job.
BatchCommand robot_batch(const RobotJob& job) {
  // --jobs alone keeps one URDF one robot (its links baked at once).
  return {"robot",
          "Links baked at once (default 0: one per core); in a batch, robots baked at once, "
          "the cores split among them",
          "Extensions a folder is scanned for (default: urdf)",
          {"urdf"},
          false,
          bake_with(RobotBatchOptions{{}, job}, bake_robot_batch)};
}

int run_robot(const RobotArgs& a) {
  // Everything that needs no work first: options, formats, the output folder.
  RobotJob job = robot_job(a);
  const BatchCommand batch = robot_batch(job);
  if (is_batch(a.urdfs, a.batch, batch)) {
    if (!a.cover_start.empty())
      throw InputError::option(ErrorKind::kConflict, "cover_start", a.cover_start,
                               "starts the outer sets of one robot, not of a batch");
    return run_batch(a.urdfs, a.out, a.batch, batch, a.quiet);
  }
  const std::string& urdf = a.urdfs.front();
  formats::check_output_dir(a.out);
  // bake_robot_file checks the URDF, its meshes and the SRDF; the start spheres are read here.
  check_output_spares_inputs(a.out, {a.cover_start});
  if (!a.quiet) {
    std::cerr << "baking " << urdf << "\n";
    job.bake.progress = print_progress;
  }
  const RobotFileResult r = bake_robot_file(urdf, a.out, job);
  if (!a.quiet && !r.bake.unused_outer_start.empty()) {
    std::cerr << "medspheres: warning: " << a.cover_start << ": "
              << count_text(r.bake.unused_outer_start.size(), "link") << " with no meshed part in "
              << urdf << ", not used:";
    for (const std::string& link : r.bake.unused_outer_start) std::cerr << " " << link;
    std::cerr << "\n";
  }
  if (!a.quiet) {
    print_summary(r.bake, a.out);
    std::cout << "the planner formats carry each link's "
              << (r.choice == formats::SphereChoice::kInner ? "inner" : "covering") << " set\n";
    print_planner_summary(
        *r.bake.model.planner, r.planner,
        formats::curobo_sphere_pairs(r.bake.model, formats::robot_spheres(r.bake.model, r.choice)),
        a.free_joints);
    for (const std::string& w : r.warnings)
      std::cerr << "medspheres: warning: " << urdf << ": " << w << "\n";
  }
  return kExitOk;
}

// The robot, its outputs and which set the planner formats carry.
void add_robot_input_options(CLI::App* sub, RobotArgs* a) {
  sub->add_option("urdf", a->urdfs,
                  "Robot description (URDF); several files or folders bake a batch, each robot "
                  "into its own folder under -o");
  sub->add_option("-o,--output", a->out,
                  "Output folder (replaced as a whole; it must not hold the inputs); a batch's "
                  "output folder")
      ->required()
      ->check(non_empty);
  sub->add_option("--format", a->formats,
                  "robot, curobo, xrdf, urdf, srdf, foam, sph (default: all)")
      ->delimiter(',');
  sub->add_option("--set", a->set,
                  "The set the planner formats carry: inner, outer, or auto (outer when "
                  "baked, else inner)")
      ->capture_default_str();
  sub->add_option("--package", a->packages, "PKG=DIR: where package://PKG/ lives (repeatable)");
  sub->add_flag("--from-visual", a->from_visual,
                "Use visual geometry for links without collision geometry");
}

// How each link is baked: budgets, resolution, dilation, solid, covers.
void add_robot_bake_options(CLI::App* sub, RobotArgs* a) {
  sub->add_option("--spheres-per-link", a->spheres_per_link,
                  "At most K spheres per link (default 32 unless --budget, --target-error or "
                  "--resolution is given)");
  sub->add_option("--budget", a->budget, "At most N spheres for the robot, shared by surface area");
  sub->add_option("--link", a->link_budgets, "NAME=K: at most K spheres for link NAME");
  sub->add_option("--resolution", a->resolution, "Grid cells along a link's longest side")
      ->capture_default_str();
  sub->add_option("--object-angle", a->object_angle, "Keep medial points at least this open (rad)")
      ->capture_default_str();
  sub->add_option("--target-error", a->target_error, "Per link: nerr at most E");
  sub->add_flag("--dilate", a->dilation.dilate,
                "Per link: grow the spheres toward the surface (S+)");
  sub->add_option("--vertex-tolerance", a->dilation.vertex_tolerance,
                  "Dilation: length (or 0.003L)");
  sub->add_option("--max-protrusion", a->dilation.max_protrusion, "Dilation: length (or 0.003L)");
  sub->add_option("--cover", a->dilation.cover,
                  "Dilation: cover the surface to this length (or L)");
  sub->add_option("--seed", a->dilation.seed, "Dilation: seed of its random points")
      ->check(non_negative)
      ->capture_default_str();
  add_solid_flags(sub, a->solid);
  add_cover_search_flags(sub, a->cover_search, "Covering sets");
  sub->add_flag("--no-measure", a->no_measure, "Skip the exact volume error of each link");
  sub->add_flag("--no-outer", a->no_outer,
                "Bake inner sets only (default: also a certified covering set per link, which "
                "the planner formats then carry)");
  sub->add_flag("--fill", a->fill,
                "Bake the inner set of a link whose solid is a thin shell (less than 0.2 of its "
                "filled solid's volume) on its filled solid, its cavity filled; its covering "
                "set stays on the real surface (docs/robots.md, Thin shells)");
  sub->add_flag("--fill-covers", a->fill_covers,
                "Bake the covering set of a thin-shelled link on its filled solid: the balls "
                "fill its cavity and hug its outside instead of sticking out on both sides of "
                "the thin material; still certified on the real surface "
                "(docs/self-collision.md, Covers of thin shells)");
  sub->add_option("--cover-start", a->cover_start,
                  "A per-link sphere file (cuRobo, XRDF, ...; link frames) whose spheres, a "
                  "planner's own set that need not cover, become each link's certified covering "
                  "set of at most as many spheres, tightened; links it lacks are baked to "
                  "their budget")
      ->check(non_empty);
}

// The planner files: tool frames, the self-collision matrix, contact-aware covers.
void add_robot_planner_options(CLI::App* sub, RobotArgs* a) {
  sub->add_option("--tool-frame", a->tool_frames,
                  "A link the planner files report (repeatable; the first is the primary end "
                  "effector; default: the SRDF's end effectors, else per branch the link that "
                  "carries the gripper or hand, else a frame fixed to the arm's end named as a "
                  "tool frame (tool0, tool_frame, tcp, ..., hand), else the arm's last link; "
                  "grippers first, then the longest chains)");
  sub->add_option("--free-joint", a->free_joints,
                  "A joint the planner files leave free although the rules lock it (a "
                  "gripper's or hand's finger joint, for in-hand planning; repeatable)");
  sub->add_option("--srdf", a->srdf,
                  "An SRDF whose disabled pairs are taken as given and whose end effectors "
                  "are the tool frames")
      ->check(non_empty);
  sub->add_flag("--no-self-collision", a->no_self_collision,
                "Skip the self-collision matrix (only adjacent pairs skipped; the default "
                "configuration not checked)");
  sub->add_option("--self-collision-samples", a->self_collision.samples,
                  "Configurations the matrix samples")
      ->check(non_negative)
      ->capture_default_str();
  sub->add_option("--self-collision-seed", a->self_collision.seed, "Seed of those samples")
      ->check(non_negative)
      ->capture_default_str();
  sub->add_option("--self-collision-threshold", a->self_collision.threshold,
                  "Share of samples in which a pair collides for it to count as always colliding")
      ->capture_default_str();
  sub->add_option("--self-collision-margin", a->self_collision.margin,
                  "Metres: a pair whose solids never come this close is never colliding")
      ->capture_default_str();
  sub->add_option("--self-collision-estimate", a->self_collision.estimate,
                  "Other random configurations over which the summary counts the files' false "
                  "self-collisions and missed ones (0: none; no file changes)")
      ->check(non_negative)
      ->capture_default_str();
  sub->add_flag("--contact", a->contact,
                "Contact-aware covers: bake the covers again to stick out less where the "
                "checked pairs come close (docs/self-collision.md)");
  sub->add_option("--contact-samples", a->contact_options.samples,
                  "Configurations the contact regions are learnt from")
      ->check(non_negative)
      ->capture_default_str();
  sub->add_option("--contact-band", a->contact_options.band,
                  "Metres: another link's surface within it of a link's makes its contact region")
      ->capture_default_str();
  sub->add_option("--contact-weight", a->contact_options.weight,
                  "How many times the protrusion of a ball in a contact region counts")
      ->capture_default_str();
  sub->add_option("--contact-min-share", a->contact_options.min_share,
                  "A contact region keeps the places partners came to in at least this share "
                  "of the samples")
      ->capture_default_str();
}

}  // namespace

Runner register_robot(CLI::App& app) {
  auto a = std::make_shared<RobotArgs>();
  CLI::App* sub = app.add_subcommand(
      "robot", "Bake every link of a URDF robot and write its spheres in the planners' formats");
  add_robot_input_options(sub, a.get());
  add_robot_bake_options(sub, a.get());
  add_robot_planner_options(sub, a.get());
  sub->add_flag("-q,--quiet", a->quiet, "No progress lines or summary");
  add_batch_flags(*sub, a->batch, robot_batch(RobotJob{}));
  return [a, sub] {
    if (a->urdfs.empty() && a->batch.from_list.empty())
      throw std::invalid_argument("robot: no URDF given (a URDF file, folders, or --from-list)");
    a->resolution_given = sub->count("--resolution") > 0;
    return run_robot(*a);
  };
}

}  // namespace medspheres::cli
