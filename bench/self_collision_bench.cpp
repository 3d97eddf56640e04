// The self-collision matrix of the robot command (docs/self-collision.md), one table per
// robot: the Unitree G1 of ../shared (when present), the coarse arm (tests/support/
// coarse_arm.h: a Panda-like chain of coarse meshes with a mimic gripper), generated arms
// (tests/support/generated_arms.h) and any --urdf given.
//
// Rows: "medspheres", the robot command's defaults (covering sets of --spheres-per-link
// spheres, the matrix from --samples seeded configurations, its tool frames and default
// configuration); with --fill-covers also "filled", the same with thin shells' covers baked
// on their filled solids (`robot --fill-covers`, at --fill-resolution); with --contact also
// "contact", the same with contact-aware covers
// (contact_regions.h: --contact-samples, --contact-band, --contact-weight); for the G1 also
// "curobo", cuRobo's shipped configuration of the G1 (its spheres, self_collision_ignore and
// self_collision_buffer, links the URDF lacks left out, its cspace default_joint_position as its
// default configuration), judged in the same run by the same code. Columns:
//   spheres           the row's spheres over the robot;
//   samples, s        the matrix's samples and wall clock (--threads pairs at once);
//   adj alw nev sph def chk giv   pairs per class (curobo: skipped pairs under "giv",
//                     the others under "chk");
//   pen@def           pairs of checked links whose spheres overlap (their buffers applied)
//                     at the row's default configuration, and the deepest overlap (mm);
//   FP cfg, FP pairs  over --eval other seeded configurations: configurations where some
//                     checked pair's spheres collide and no pair of solids does, and the
//                     (configuration, pair) cases where a checked pair's spheres collide
//                     and its solids do not;
//   FN cfg, FN pairs  configurations where some checked pair's solids collide and no
//                     checked pair's spheres do, and the (configuration, pair) cases where
//                     a checked pair's solids collide and its spheres do not;
//   skipped hits      (configuration, pair) cases where the solids of a pair the row skips
//                     collide (adjacent and always-colliding pairs of the medspheres
//                     matrix excepted): what skipping costs.
// The evaluation's configurations hold the medspheres row's locked joints (the gripper's) at
// their default, as a planner given its files holds them; the other joints are uniform
// within their limits.
// The solids: each link's exact geometry (LinkSolids: certified sphere bounds, FCL's exact
// mesh distance where they leave it open); "collide" means touching. Pairs judged: every
// two links with geometry in both rows' sets, except the medspheres matrix's adjacent and
// always-colliding pairs, the same for both rows.
//
// What-ifs on the medspheres row: --link NAME=K bakes link NAME to K spheres (the others to
// --spheres-per-link); --buffer NAME=M adds M metres to its self-collision buffer (negative:
// its spheres shrink and no longer cover, so false negatives may appear); --cover-start FILE
// tightens the covers of the links FILE names from its spheres, in every row (`robot
// --cover-start`). Diagnostics:
// --gaps N tallies, for each row's N pairs that alone make the most false-positive
// configurations, the evaluation's configurations by the pair's mesh gap and how many of
// them its spheres report; --ideal D (repeatable) counts the false-positive configurations
// of an ideal planner that checks the medspheres row's pairs and reports a pair exactly when
// its solids are within D, the least a cover sticking out by D / 2 everywhere can reach;
// with --fill-covers, the free configurations where a checked partner meets a filled link's
// filled solid (the least its cover reports).
//
// Usage: bench_self_collision [--urdf FILE]... [--samples N] [--eval N] [--seed S]
//          [--spheres-per-link K] [--link NAME=K]... [--buffer NAME=M]... [--gaps N]
//          [--ideal D]... [--cover-start FILE] [--fill-covers [--fill-resolution N]]
//          [--contact ...] [--arms N] [--threads T] [--cache DIR] [--no-g1] [--no-coarse-arm]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include "bench_args.h"
#include "medspheres/batch/batch_robot.h"
#include "medspheres/error.h"
#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/formats/curobo_yaml.h"
#include "medspheres/formats/self_collision_report.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/io.h"
#include "medspheres/measure/fit_metrics.h"
#include "medspheres/mesh/filled_solid.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/number_text.h"
#include "medspheres/robot_bake/contact_regions.h"
#include "medspheres/robot_bake/robot_planner_setup.h"
#include "medspheres/robot_file.h"
#include "medspheres/sha256.h"
#include "solid_flags.h"
#include "support/coarse_arm.h"
#include "support/generated_arms.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using namespace medspheres;
using Poses = std::vector<Eigen::Isometry3d>;

struct Options {
  std::vector<std::string> urdfs;
  std::size_t samples = 10000;
  std::size_t eval = 10000;
  unsigned seed = 1;
  std::size_t spheres_per_link = kDefaultSpheresPerLink;
  int arms = 2;
  int threads = 2;
  std::string cache;
  bool g1 = true;
  bool coarse_arm = true;
  std::size_t top = 0;                         // pairs named per row
  std::size_t gaps = 0;                        // pairs whose gaps are tallied, per row
  std::vector<double> ideal;                   // margins of the ideal planner, metres
  std::vector<std::string> link_budgets;       // NAME=K
  std::vector<std::string> buffers;            // NAME=M, added to the medspheres row's
  std::string cover_start;                     // a per-link sphere file the covers start from
  bool fill_covers = false;                    // add the row of thin shells' covers filled
  CoverSearch cover_search;                    // of every row's covers (robot's flags)
  int fill_resolution = kFillCoverResolution;  // of their filled solid
  bool contact = false;                        // add the contact-aware row
  bool contact_regions = false;                // and print its regions' protrusions
  ContactOptions contact_options;
};

// NAME=VALUE options as (NAME, VALUE).
std::vector<std::pair<std::string, double>> name_values(const std::vector<std::string>& texts,
                                                        const std::string& option) {
  std::vector<std::pair<std::string, double>> out;
  for (const std::string& text : texts) {
    const std::size_t eq = text.find('=');
    char* end = nullptr;
    const double v = eq == std::string::npos ? 0.0 : std::strtod(text.c_str() + eq + 1, &end);
    if (eq == std::string::npos || end == text.c_str() + eq + 1 || *end != '\0')
      throw InputError(option, "expected NAME=VALUE, got '" + text + "'");
    out.emplace_back(text.substr(0, eq), v);
  }
  return out;
}

// A robot baked as the robot command bakes it (cached under the batch cache's key).
struct Baked {
  std::string name;
  RobotModel model;
  std::vector<LinkSolid> solids;
};

RobotJob robot_job(const Options& o, bool fill_covers = false) {
  RobotJob job;
  job.bake.fill_thin_shell_covers = fill_covers;
  job.bake.fill_cover_resolution = o.fill_resolution;
  if (!o.cover_start.empty())
    job.bake.outer_start = formats::read_link_sphere_map(o.cover_start, "--cover-start");
  job.bake.budget.per_link = o.spheres_per_link;
  for (const auto& [link, k] : name_values(o.link_budgets, "--link"))
    job.bake.budget.links[link] = static_cast<std::size_t>(k);
  job.bake.jobs = o.threads;
  job.bake.request.measure = false;
  job.bake.request.cover_search = o.cover_search;
  return job;
}

// \p make()'s model, or the one cached under \p name.
template <class Make>
RobotModel cached_model(const Options& o, const std::string& name, const Make& make) {
  const fs::path cached = fs::path(o.cache) / name;
  if (!o.cache.empty() && fs::exists(cached)) return load_robot(cached.string());
  RobotModel model = make();
  if (!o.cache.empty()) {
    fs::create_directories(o.cache);
    save_robot(model, cached.string());
  }
  return model;
}

// The robot command's bake; with \p contact the contact-aware one (rebake_contact_aware, the
// matrix as the medspheres row computes it); with \p fill_covers thin shells' covers baked on
// their filled solids (`robot --fill-covers`).
Baked bake(const std::string& urdf, const Options& o, bool contact = false,
           bool fill_covers = false) {
  const UrdfRobot robot = read_urdf(urdf);
  Baked b;
  b.name = robot.model.name;
  b.solids = load_link_solids(robot);
  const RobotJob job = robot_job(o, fill_covers);
  const std::string key =
      robot_cache_key(robot, file_sha256(urdf), job, fs::path(urdf).filename().string());
  b.model = cached_model(o, key + ".robot.json",
                         [&] { return bake_robot(robot, b.solids, job.bake).model; });
  if (!contact) return b;
  const ContactOptions& c = o.contact_options;
  const std::string suffix = ".contact-" + std::to_string(c.samples) + "-" +
                             exact_number_text(c.band) + "-" + exact_number_text(c.weight) + "-" +
                             exact_number_text(c.min_share);
  b.model = cached_model(o, key + suffix + ".robot.json", [&] {
    RobotBakeResult first;
    first.model = b.model;
    PlannerRequest r;
    r.self_collision.samples = o.samples;
    r.self_collision.seed = o.seed;
    r.self_collision.threads = o.threads;
    const auto t0 = std::chrono::steady_clock::now();
    RobotModel m =
        rebake_contact_aware(robot, b.solids, job.bake, first, formats::SphereChoice::kOuter, r, c)
            .model;
    std::printf("  contact: regions and second bake in %.1f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return m;
  });
  return b;
}

// One row's planner: its spheres with their buffers, the pairs it checks, its default.
struct Planner {
  std::string row;
  std::size_t sphere_count = 0;
  PlannerSpheres spheres;
  std::set<std::pair<std::size_t, std::size_t>> checked;  // link indices, a < b
  std::map<std::string, double> default_positions;
  std::vector<std::string> locked_joints;  // held at their default while planning
  std::map<PairClass, std::size_t> classes;
  std::size_t samples = 0;
  double seconds = 0.0;
};

using LinkPair = std::pair<std::size_t, std::size_t>;

// The pair of the two links' indices, smaller first.
LinkPair ordered(const RobotModel& m, const std::string& a, const std::string& b);

std::size_t index_of(const RobotModel& m, const std::string& name) {
  for (std::size_t i = 0; i < m.links.size(); ++i)
    if (m.links[i].name == name) return i;
  return m.links.size();
}

LinkPair ordered(const RobotModel& m, const std::string& a, const std::string& b) {
  const std::size_t i = index_of(m, a), j = index_of(m, b);
  return {std::min(i, j), std::max(i, j)};
}

Planner medspheres_planner(const Baked& b, const Options& o,
                           std::set<std::pair<std::size_t, std::size_t>>& judged,
                           const std::string& row = "medspheres") {
  PlannerRequest r;
  r.self_collision.samples = o.samples;
  r.self_collision.seed = o.seed;
  r.self_collision.threads = o.threads;
  // The table counts false positives and negatives itself, over the same configurations
  // as the robot command's estimate (seed + 7919), for every row alike.
  r.self_collision.estimate = 0;
  SelfCollisionRun run;
  const PlannerSetup s =
      make_planner_setup(b.model, b.solids, formats::SphereChoice::kOuter, r, &run);
  std::map<std::string, double> buffer = s.self_collision->buffer;
  for (const auto& [link, m] : name_values(o.buffers, "--buffer")) {
    if (!buffer.count(link))
      throw InputError("--buffer", "no link with spheres named '" + link + "' in " + b.name);
    buffer[link] += m;
  }
  Planner p{row,
            0,
            PlannerSpheres(b.model, formats::robot_spheres(b.model), buffer),
            {},
            s.default_positions,
            s.locked_joints,
            {},
            o.samples,
            run.seconds};
  for (const formats::LinkSphereList& l : formats::robot_spheres(b.model))
    p.sphere_count += l.spheres.size();
  for (const auto& [kind, n] : formats::pair_class_counts(*s.self_collision))
    p.classes[kind] = n.first;
  for (const LinkPairClass& q : s.self_collision->pairs) {
    const LinkPair pair = ordered(b.model, q.link1, q.link2);
    if (!q.ignored) p.checked.insert(pair);
    if (q.kind != PairClass::kAdjacent && q.kind != PairClass::kAlways) judged.insert(pair);
  }
  std::printf("  %s: tool frames", row.c_str());
  for (const std::string& t : s.tool_frames) std::printf(" %s", t.c_str());
  std::printf("; default configuration: %s\n", default_from_text(s.default_from).c_str());
  return p;
}

// cuRobo's shipped G1 configuration, restricted to the links of the URDF.
Planner curobo_planner(const Baked& b, const std::string& yml) {
  const YAML::Node k = YAML::LoadFile(yml)["kinematics"];
  formats::RobotSpheres spheres;
  for (formats::LinkSphereList& l : formats::load_curobo_yaml(yml))
    if (index_of(b.model, l.link) < b.model.links.size()) spheres.push_back(std::move(l));
  std::map<std::string, double> buffer;
  for (const auto& kv : k["self_collision_buffer"])
    buffer[kv.first.as<std::string>()] = kv.second.as<double>();
  Planner p{"curobo", 0, PlannerSpheres(b.model, spheres, buffer), {}, {}, {}, {}, 0, 0.0};
  for (const formats::LinkSphereList& l : spheres) p.sphere_count += l.spheres.size();
  std::set<std::pair<std::string, std::string>> skip;
  for (const auto& kv : k["self_collision_ignore"])
    for (const auto& other : kv.second)
      skip.insert(std::minmax(kv.first.as<std::string>(), other.as<std::string>()));
  for (std::size_t a = 0; a < spheres.size(); ++a)
    for (std::size_t c = a + 1; c < spheres.size(); ++c) {
      const LinkPair pair = ordered(b.model, spheres[a].link, spheres[c].link);
      if (skip.count(std::minmax(spheres[a].link, spheres[c].link)))
        ++p.classes[PairClass::kGiven];
      else
        p.checked.insert(pair), ++p.classes[PairClass::kChecked];
    }
  const auto names = k["cspace"]["joint_names"].as<std::vector<std::string>>();
  const auto q = k["cspace"]["default_joint_position"].as<std::vector<double>>();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (b.model.find_joint(names[i])) p.default_positions[names[i]] = q[i];
  return p;
}

struct Tally {
  std::size_t pen_pairs = 0;
  double pen_max = 0.0;
  std::size_t fp_cfg = 0, fp_pairs = 0, fn_cfg = 0, fn_pairs = 0, skipped_hits = 0;
  std::map<LinkPair, std::size_t> fp_by_pair;       // the configurations where only it is FP
  std::map<LinkPair, std::size_t> skipped_by_pair;  // the configurations where it is a hit
};

Tally judge(const Baked& b, const LinkSolids& solids, const Planner& p,
            const std::set<std::pair<std::size_t, std::size_t>>& judged,
            const std::vector<Poses>& eval, const std::vector<std::vector<char>>& truth) {
  Tally t;
  const KinematicTree tree(b.model);
  std::map<std::string, double> q0;
  for (const std::string& j : tree.joint_names()) {
    const auto it = p.default_positions.find(j);
    q0[j] = it == p.default_positions.end() ? 0.0 : it->second;
  }
  const Poses X0 = tree.link_poses(q0);
  for (const auto& [a, c] : p.checked) {
    const double pen = p.spheres.penetration(X0, a, c);
    if (pen > 0) ++t.pen_pairs, t.pen_max = std::max(t.pen_max, pen);
  }
  const std::vector<std::pair<std::size_t, std::size_t>> pairs(judged.begin(), judged.end());
  for (std::size_t s = 0; s < eval.size(); ++s) {
    bool any_solid = false, any_checked_solid = false;
    std::vector<LinkPair> colliding;  // checked pairs whose spheres collide
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const bool solid = truth[s][k];
      any_solid = any_solid || solid;
      if (!p.checked.count(pairs[k])) {
        t.skipped_hits += solid;
        if (solid) ++t.skipped_by_pair[pairs[k]];
        continue;
      }
      const bool sphere = p.spheres.collide(eval[s], pairs[k].first, pairs[k].second);
      if (sphere) colliding.push_back(pairs[k]);
      any_checked_solid = any_checked_solid || solid;
      t.fp_pairs += sphere && !solid;
      t.fn_pairs += solid && !sphere;
    }
    // The row's checked pairs that are not judged (adjacent or always colliding ones it
    // checks) count too: the planner reports the configuration in collision.
    for (const LinkPair& c : p.checked)
      if (!judged.count(c) && p.spheres.collide(eval[s], c.first, c.second)) colliding.push_back(c);
    const bool any_sphere = !colliding.empty();
    t.fp_cfg += any_sphere && !any_solid;
    if (any_sphere && !any_solid && colliding.size() == 1) ++t.fp_by_pair[colliding[0]];
    t.fn_cfg += any_checked_solid && !any_sphere;
  }
  (void)solids;
  return t;
}

// For the row's top `o.gaps` pairs of one-pair false positives: over the evaluation's
// configurations where the pair's solids do not collide, how many have them within 1, 2,
// 5, 10, 20, 40 mm and farther, and in how many of each the row's spheres collide. A
// covering set reports a collision wherever the gap is below the two links' protrusions
// there, so the first columns bound what any cover of that tightness can reach.
void print_gaps(const Baked& b, const LinkSolids& solids, const Planner& p, const Tally& t,
                const std::vector<Poses>& eval, std::size_t n) {
  const double ds[] = {0.001, 0.002, 0.005, 0.01, 0.02, 0.04};
  constexpr int kBins = 7;
  std::vector<std::pair<std::size_t, LinkPair>> top;
  for (const auto& [pair, count] : t.fp_by_pair) top.emplace_back(count, pair);
  std::sort(top.rbegin(), top.rend());
  for (std::size_t k = 0; k < top.size() && k < n; ++k) {
    const auto [a, c] = top[k].second;
    std::size_t all[kBins] = {0}, fp[kBins] = {0};
    for (const Poses& X : eval) {
      if (solids.within(X, a, c, 0.0)) continue;
      int bin = kBins - 1;
      while (bin > 0 && solids.within(X, a, c, ds[bin - 1])) --bin;
      ++all[bin];
      fp[bin] += p.spheres.collide(X, a, c);
    }
    std::printf("  %s: gaps of %s-%s (<=1 <=2 <=5 <=10 <=20 <=40 >40 mm): configurations",
                p.row.c_str(), b.model.links[a].name.c_str(), b.model.links[c].name.c_str());
    for (int i = 0; i < kBins; ++i) std::printf(" %zu", all[i]);
    std::printf("; spheres collide in");
    for (int i = 0; i < kBins; ++i) std::printf(" %zu", fp[i]);
    std::printf("\n");
  }
}

// False-positive configurations of an ideal planner that checks the row's pairs and reports
// a pair exactly when its solids are within d: what a cover sticking out by d/2 everywhere,
// and no more, would give. The least any cover of that tightness can reach.
void print_ideal(const LinkSolids& solids, const Planner& p,
                 const std::set<std::pair<std::size_t, std::size_t>>& judged,
                 const std::vector<Poses>& eval, const std::vector<std::vector<char>>& truth,
                 const std::vector<double>& margins, int threads) {
  const std::vector<LinkPair> pairs(judged.begin(), judged.end());
  std::printf(
      "  %s: ideal planner on its checked pairs (reports a pair when its solids are "
      "within d): FP cfg",
      p.row.c_str());
  for (const double d : margins) {
    std::size_t fp = 0;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads) reduction(+ : fp)
    for (std::size_t s = 0; s < eval.size(); ++s) {
      if (std::find(truth[s].begin(), truth[s].end(), 1) != truth[s].end()) continue;
      bool near = false;
      for (std::size_t k = 0; k < pairs.size() && !near; ++k)
        near =
            p.checked.count(pairs[k]) && solids.within(eval[s], pairs[k].first, pairs[k].second, d);
      fp += near;
    }
    std::printf(" %g mm: %zu;", 1e3 * d, fp);
  }
  std::printf("\n");
}

// The links whose covering set was baked on their filled solid (the robot's metadata:
// "cover_solid": "filled" in the link's entry).
std::vector<std::size_t> filled_links(const RobotModel& m) {
  const nlohmann::json links = nlohmann::json::parse(m.metadata_json)["links"];
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const auto it = links.find(m.links[i].name);
    if (it != links.end() && it->value("cover_solid", "") == "filled") out.push_back(i);
  }
  return out;
}

// The solids with each filled link's solid replaced by its filled solid (at the bake's
// resolution; in the part's frame, as the bake builds it, then placed), bounded by the
// real link's inner set (inside the real solid, so inside the filled one) and the filled
// row's cover (certified on the filled solid's boundary).
LinkSolids filled_solids(const Baked& b, const std::vector<std::size_t>& links, int resolution) {
  RobotModel model = b.model;
  std::vector<LinkSolid> solids = b.solids;
  for (const std::size_t i : links) {
    LinkSolid& s = solids[i];
    const bool one = s.parts.size() == 1;
    TriangleMesh mesh =
        make_filled_solid(one ? s.parts[0].mesh : s.placed_mesh(), s.link, resolution).mesh;
    if (one)
      for (Eigen::Vector3d& v : mesh.vertices) v = s.parts[0].origin * v;
    LinkSolidPart part;
    part.mesh = std::move(mesh);
    part.source = "filled " + s.link;
    s.parts = {std::move(part)};
    s.spheres.clear();
  }
  return LinkSolids(model, solids);
}

// The least the filled covers can reach: over the evaluation's configurations where no pair
// of real solids collides, those where some checked pair collides once each filled link's
// solid is its filled solid (a partner enters a cavity's closing or the filled solid's
// excess), per filled link and over all: a cover of the filled solid reports them all.
void print_filled_floor(const Baked& filled, const Planner& p,
                        const std::set<std::pair<std::size_t, std::size_t>>& judged,
                        const std::vector<Poses>& eval, const std::vector<std::vector<char>>& truth,
                        const Options& o) {
  const std::vector<std::size_t> links = filled_links(filled.model);
  if (links.empty()) return;
  const LinkSolids solids = filled_solids(filled, links, o.fill_resolution);
  const std::vector<LinkPair> pairs(judged.begin(), judged.end());
  // hits[s][l]: a checked partner meets filled link l's filled solid in free configuration s
  std::vector<std::vector<char>> hits(eval.size(), std::vector<char>(links.size(), 0));
#pragma omp parallel for schedule(dynamic, 16) num_threads(o.threads)
  for (std::size_t s = 0; s < eval.size(); ++s) {
    if (std::find(truth[s].begin(), truth[s].end(), 1) != truth[s].end()) continue;
    for (std::size_t l = 0; l < links.size(); ++l)
      for (std::size_t k = 0; k < pairs.size() && !hits[s][l]; ++k) {
        const auto [a, c] = pairs[k];
        if ((a != links[l] && c != links[l]) || !p.checked.count(pairs[k])) continue;
        hits[s][l] = solids.has(a) && solids.has(c) && solids.within(eval[s], a, c, 0.0);
      }
  }
  std::vector<std::size_t> per_link(links.size(), 0);
  std::size_t any = 0;
  for (const std::vector<char>& h : hits) {
    for (std::size_t l = 0; l < links.size(); ++l) per_link[l] += h[l];
    any += std::find(h.begin(), h.end(), 1) != h.end();
  }
  std::printf("  %s: free configurations where a checked partner meets a filled solid:",
              p.row.c_str());
  for (std::size_t l = 0; l < links.size(); ++l)
    std::printf(" %s %zu;", filled.model.links[links[l]].name.c_str(), per_link[l]);
  std::printf(" any %zu (of %zu)\n", any, eval.size());
}

void print_row(const Planner& p, const Tally& t, std::size_t eval) {
  const auto n = [&](PairClass k) {
    const auto it = p.classes.find(k);
    return it == p.classes.end() ? std::size_t{0} : it->second;
  };
  std::printf(
      "%-11s %7zu %7zu %6.2f %4zu %4zu %4zu %4zu %4zu %4zu %4zu %4zu/%-6.1f %6zu %6zu %8zu %6zu "
      "%8zu %8zu\n",
      p.row.c_str(), p.sphere_count, p.samples, p.seconds, n(PairClass::kAdjacent),
      n(PairClass::kAlways), n(PairClass::kNever), n(PairClass::kSphereOnly),
      n(PairClass::kDefault), n(PairClass::kChecked), n(PairClass::kGiven), t.pen_pairs,
      1e3 * t.pen_max, eval, t.fp_cfg, t.fp_pairs, t.fn_cfg, t.fn_pairs, t.skipped_hits);
}

// Per link with a contact region (the regions recomputed from the first bake's matrix): the
// largest protrusion of its covering balls that reach the region, in the first bake and in
// the contact-aware one, and of the contact-aware one's other balls (mm): what the weights
// bought where the partners come.
void print_contact_protrusions(const Baked& first, const Baked& contact, const Options& o) {
  PlannerRequest r;
  r.self_collision.samples = o.samples;
  r.self_collision.seed = o.seed;
  r.self_collision.threads = o.threads;
  const PlannerSetup s =
      make_planner_setup(first.model, first.solids, formats::SphereChoice::kOuter, r);
  std::map<std::string, double> locked;
  for (const std::string& j : s.locked_joints) locked[j] = s.default_positions.at(j);
  const auto regions =
      contact_regions(first.model, first.solids, *s.self_collision, locked, o.contact_options);
  std::printf(
      "  contact regions (link: points; mm stuck out by the balls reaching it, first -> "
      "contact; the other balls):\n");
  for (std::size_t i = 0; i < first.model.links.size(); ++i) {
    const auto it = regions.find(first.model.links[i].name);
    if (it == regions.end()) continue;
    const MeshQuery query(first.solids[i].placed_mesh());
    const auto split = [&](const std::vector<Sphere>& balls) {
      const std::vector<double> p = sphere_protrusions(query, balls, o.threads);
      std::pair<double, double> out{0.0, 0.0};
      for (std::size_t k = 0; k < balls.size(); ++k) {
        const bool reaches = std::any_of(
            it->second.points.begin(), it->second.points.end(), [&](const Eigen::Vector3d& q) {
              return (q - balls[k].center).norm() <= balls[k].radius + it->second.reach;
            });
        double& into = reaches ? out.first : out.second;
        into = std::max(into, p[k]);
      }
      return out;
    };
    const auto a = split(first.model.links[i].spheres.outer.spheres);
    const auto c = split(contact.model.links[i].spheres.outer.spheres);
    std::printf("    %s: %zu; %.1f -> %.1f; %.1f\n", it->first.c_str(), it->second.points.size(),
                1e3 * a.first, 1e3 * c.first, 1e3 * c.second);
  }
}

void run_robot(const std::string& urdf, const std::string& curobo_yml, const Options& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const Baked b = bake(urdf, o);
  std::printf("\n%s (%s; %zu spheres a link, baked or read in %.1f s)\n", b.name.c_str(),
              urdf.c_str(), o.spheres_per_link,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  std::set<std::pair<std::size_t, std::size_t>> judged;
  std::vector<Planner> rows;
  rows.push_back(medspheres_planner(b, o, judged));
  std::optional<Baked> filled;
  if (o.fill_covers) {
    filled = bake(urdf, o, false, true);
    rows.push_back(medspheres_planner(*filled, o, judged, "filled"));
  }
  if (o.contact) {
    const Baked c = bake(urdf, o, true);
    rows.push_back(medspheres_planner(c, o, judged, "contact"));
    if (o.contact_regions) print_contact_protrusions(b, c, o);
  }
  if (!curobo_yml.empty()) rows.push_back(curobo_planner(b, curobo_yml));
  // The evaluation's configurations and, per pair judged, whether the solids collide.
  const LinkSolids solids(b.model, b.solids);
  const KinematicTree tree(b.model);
  // The locked joints (the gripper's) held at their default, as the planner holds them.
  std::vector<Eigen::VectorXd> qs =
      medspheres::fcl::sample_configurations(b.model, tree, o.eval, o.seed + 7919);
  const std::vector<std::string>& names = tree.joint_names();
  for (const std::string& j : rows[0].locked_joints) {
    const std::size_t k = std::find(names.begin(), names.end(), j) - names.begin();
    for (Eigen::VectorXd& q : qs) q[k] = rows[0].default_positions.at(j);
  }
  std::vector<Poses> eval(qs.size());
  std::vector<std::vector<char>> truth(qs.size());
  const std::vector<std::pair<std::size_t, std::size_t>> pairs(judged.begin(), judged.end());
#pragma omp parallel for schedule(dynamic, 16) num_threads(o.threads)
  for (std::size_t s = 0; s < qs.size(); ++s) {
    eval[s] = tree.link_poses(qs[s]);
    for (const auto& [a, c] : pairs)
      truth[s].push_back(solids.has(a) && solids.has(c) && solids.within(eval[s], a, c, 0.0));
  }
  std::printf("%-11s %7s %7s %6s %4s %4s %4s %4s %4s %4s %4s %11s %6s %6s %8s %6s %8s %8s\n",
              "planner", "spheres", "samples", "s", "adj", "alw", "nev", "sph", "def", "chk", "giv",
              "pen@def/mm", "eval", "FP cfg", "FP pairs", "FN cfg", "FN pairs", "skip hit");
  std::vector<Tally> tallies;
  for (const Planner& p : rows) {
    tallies.push_back(judge(b, solids, p, judged, eval, truth));
    print_row(p, tallies.back(), o.eval);
  }
  if (!o.ideal.empty()) print_ideal(solids, rows[0], judged, eval, truth, o.ideal, o.threads);
  if (filled) print_filled_floor(*filled, rows[1], judged, eval, truth, o);
  for (std::size_t r = 0; r < rows.size() && o.gaps > 0; ++r)
    print_gaps(b, solids, rows[r], tallies[r], eval, o.gaps);
  if (o.top == 0) return;
  const auto print_top = [&](const std::map<LinkPair, std::size_t>& counts, const char* what,
                             const std::string& row) {
    std::vector<std::pair<std::size_t, LinkPair>> top;
    for (const auto& [pair, n] : counts) top.emplace_back(n, pair);
    std::sort(top.rbegin(), top.rend());
    std::printf("  %s: %s:", row.c_str(), what);
    for (std::size_t k = 0; k < top.size() && k < o.top; ++k)
      std::printf(" %s-%s %zu;", b.model.links[top[k].second.first].name.c_str(),
                  b.model.links[top[k].second.second].name.c_str(), top[k].first);
    std::printf("\n");
  };
  for (std::size_t r = 0; r < rows.size(); ++r) {
    print_top(tallies[r].fp_by_pair, "false-positive configurations with one pair's spheres alone",
              rows[r].row);
    print_top(tallies[r].skipped_by_pair, "skipped pairs whose solids collide", rows[r].row);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  o.cache = xdg ? std::string(xdg) + "/medspheres/bench_self_collision"
                : std::string(home ? home : ".") + "/.cache/medspheres/bench_self_collision";
  medspheres::bench::Args args("bench_self_collision",
                               "The self-collision matrix: classes, time, default configuration, "
                               "false positives and negatives against the exact solids");
  args.app().add_option("--urdf", o.urdfs, "Another robot (repeatable)");
  args.add("--samples", o.samples, "Configurations the matrix samples");
  args.add("--eval", o.eval,
           "Other configurations the false positives and negatives are counted over");
  args.add("--seed", o.seed, "Seed of the matrix's samples (the evaluation's: seed + 7919)");
  args.add("--spheres-per-link", o.spheres_per_link, "Covering set budget per link");
  args.app().add_option("--link", o.link_budgets, "NAME=K: K spheres for link NAME (repeatable)");
  args.app().add_option("--buffer", o.buffers,
                        "NAME=M: add M metres to link NAME's self-collision buffer in the "
                        "medspheres row (negative: the spheres shrink and no longer cover)");
  args.add("--cover-start", o.cover_start,
           "A per-link sphere file: those links' covers are tightened from its spheres "
           "(robot --cover-start), in every row");
  cli::add_cover_search_flags(&args.app(), o.cover_search, "Every row's covers");
  args.app().add_flag("--fill-covers", o.fill_covers,
                      "Add the row of thin shells' covers baked on their filled solids (robot "
                      "--fill-covers) and what their filled solids alone report");
  args.add("--fill-resolution", o.fill_resolution,
           "With --fill-covers: the filled solid's resolution (cells along L)");
  args.app().add_flag("--contact", o.contact,
                      "Add the row of contact-aware covers (contact_regions.h)");
  args.app().add_flag("--contact-regions", o.contact_regions,
                      "With --contact: print each contact region's protrusions");
  args.add("--contact-samples", o.contact_options.samples,
           "Configurations the contact regions are learnt from");
  args.add("--contact-band", o.contact_options.band,
           "Metres: partners' points within it of a link make its contact region");
  args.add("--contact-min-share", o.contact_options.min_share,
           "Keep the region's cells partners came to in at least this share of the samples");
  args.add("--contact-weight", o.contact_options.weight,
           "How many times a contact ball's protrusion counts");
  args.add("--arms", o.arms, "Generated arms (seeds 1..N, 6 joints)");
  args.add("--threads", o.threads, "Pairs at once");
  args.add("--cache", o.cache, "Folder of cached bakes ('' for none)");
  args.add("--top", o.top, "Name the pairs that alone make the most false-positive configurations");
  args.add("--gaps", o.gaps,
           "Tally the mesh gaps of the pairs that alone make the most false-positive "
           "configurations (this many per row)");
  args.app().add_option("--ideal", o.ideal,
                        "Margin d (metres, repeatable): false-positive configurations of a "
                        "planner reporting the medspheres row's pairs when their solids are "
                        "within d");
  args.app().add_flag(
      "--no-g1", [&](std::int64_t) { o.g1 = false; }, "Leave out the G1");
  args.app().add_flag(
      "--no-coarse-arm", [&](std::int64_t) { o.coarse_arm = false; }, "Leave out the coarse arm");
  args.parse(argc, argv);
  try {
    const fs::path g1 = fs::path(MEDSPHERES_SOURCE_DIR) / "../shared/robots/unitree_g1";
    if (o.g1 && fs::exists(g1 / "g1_29dof_rev_1_0.urdf"))
      run_robot((g1 / "g1_29dof_rev_1_0.urdf").string(), (g1 / "curobo_unitree_g1.yml").string(),
                o);
    const medspheres::test::TempDir scratch;  // the generated robots, removed at the end
    const fs::path& dir = scratch.path();
    if (o.coarse_arm) run_robot(medspheres::test::write_coarse_arm(dir / "coarse_arm"), "", o);
    for (int seed = 1; seed <= o.arms; ++seed) {
      const fs::path urdf = dir / ("generated_arm_" + std::to_string(seed) + ".urdf");
      medspheres::write_file_atomically(
          urdf.string(), medspheres::test::generated_arm_urdf(static_cast<unsigned>(seed), 6));
      run_robot(urdf.string(), "", o);
    }
    for (const std::string& u : o.urdfs) run_robot(u, "", o);
  } catch (const medspheres::Error& e) {
    std::fprintf(stderr, "bench_self_collision: %s\n", e.what());
    return 2;
  }
  return 0;
}
