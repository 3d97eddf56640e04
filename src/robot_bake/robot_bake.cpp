// Baking a robot: one bake per distinct link geometry and budget, run on a pool of
// threads, gathered in link order.
#include "medspheres/robot_bake/robot_bake.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "filled_inner.h"
#include "medspheres/error.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/mesh/cover_certificate_json.h"
#include "medspheres/mesh/mesh_report.h"
#include "medspheres/number_text.h"
#include "medspheres/thread_option.h"
#include "medspheres/threads.h"
#include "medspheres/version.h"

namespace medspheres {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// One bake: a mesh, in a part's frame (one part) or the link frame (several), to a budget.
struct BakeJob {
  std::size_t link = 0;  ///< the first link that needs it
  std::optional<std::size_t> budget;
  BakeOutcome outcome;
  std::optional<BakeOutcome> outer;  ///< the cover, when outer sets are baked
  std::vector<Sphere> outer_start;   ///< what the cover starts from, in the bake's frame
  ProtrusionWeights outer_weights;   ///< the cover's weights, in the bake's frame
  double seconds = 0.0;
  double outer_seconds = 0.0;  ///< of seconds, the cover's
  std::exception_ptr error;
};

// Identifies what a link's bake computes: the geometry (origin-free for a single part)
// and the budget.
std::string job_key(const LinkSolid& solid, const std::optional<std::size_t>& budget) {
  std::string key;
  if (solid.parts.size() == 1) {
    key = solid.parts[0].key;
  } else {
    for (const LinkSolidPart& part : solid.parts) {
      key += part.key + " at";
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) key += " " + exact_number_text(part.origin.matrix()(r, c));
      key += "; ";
    }
  }
  return key + " budget " + (budget ? std::to_string(*budget) : std::string("none"));
}

// The spheres of a part's bake moved to the link frame, each radius shrunk to cover the
// rounding of the move (file comment of robot_bake.h). The derivation: fl(R c + t) differs
// from the exact image of c by at most about 3 eps (|R| |c| + |t|) per coordinate, and the
// rotation built from the URDF's rpy or quaternion is orthogonal to a few eps, which moves
// a point at distance r from c by a few eps r relative to the placed mesh (whose vertices
// went through the same matrix); 16 eps (3 |c| + |t| + r) bounds both with room to spare.
// A sphere too small to survive the shrink is dropped. A covering set's spheres are grown
// by the same bound instead (\p grow), so that they still hold the placed surface.
std::vector<Sphere> placed(const std::vector<Sphere>& spheres, const Eigen::Isometry3d& x,
                           bool grow = false) {
  const double eps = std::numeric_limits<double>::epsilon();
  const double t = x.translation().norm();
  std::vector<Sphere> out;
  out.reserve(spheres.size());
  for (const Sphere& s : spheres) {
    const double slack = 16.0 * eps * (3.0 * s.center.norm() + t + s.radius);
    const double r = grow ? s.radius + slack : s.radius - slack;
    if (r > 0.0) out.push_back({x * s.center, r});
  }
  return out;
}

// Which of a thin-shelled link's sets are baked on its filled solid (RobotBakeOptions).
struct FillChoice {
  bool inner = false;
  bool covers = false;
  int resolution = kFillCoverResolution;  ///< the covers' filled solid's
};

// The cover of a job's mesh to the job's budget (the request's, or the default).
// With \p fill_covers, a thin shell's cover is baked on its filled solid (filled_inner.h).
BakeOutcome bake_outer(const FitEvaluator& fit, const MeshReport& report, const BakeRequest& inner,
                       const BakeJob& job, const std::string& name, const std::string& sha256,
                       const FillChoice& fill, double fraction) {
  BakeRequest request;
  request.method = BakeMethod::kCover;
  request.medial.threads = inner.medial.threads;
  request.seed = inner.seed;
  request.solid = inner.solid;
  request.robust = inner.robust;
  request.robust_thickness = inner.robust_thickness;
  request.record_seconds = inner.record_seconds;
  request.max_spheres = job.budget ? job.budget : inner.max_spheres;
  if (!request.max_spheres) request.max_spheres = kDefaultSpheresPerLink;
  if (!job.outer_start.empty()) {  // the link's own spheres are its budget
    request.max_spheres.reset();
    request.cover_start = job.outer_start;
  } else {
    request.cover_weights = job.outer_weights;
    request.cover_search = inner.cover_search;
  }
  if (fill.covers) {
    std::optional<BakeOutcome> filled = bake_filled_cover(fit.query().mesh(), report, request, name,
                                                          sha256, fraction, fill.resolution);
    if (filled) return std::move(*filled);
  }
  return bake_mesh(fit, report, request, name, sha256);
}

// What the robot file records of an outer set's certificate: the certificate's own keys
// (cover_certificate_json), what it says of the link's sets, and
// `gap`: how much every radius grew past the certified cover of the link's mesh so that it
// also covers the true surface of primitives meshed inside it (LinkSolid::surface_gap).
std::string outer_certificate_json(const CoverResult& cover, bool moved, double gap) {
  nlohmann::ordered_json j =
      nlohmann::ordered_json::parse(cover_certificate_json(cover.certificate));
  j["surface_covered"] = cover.certificate.certified;
  j["interior_certified"] = false;
  j["moved_to_link_frame"] = moved;
  j["primitive_surface_gap"] = gap;
  return j.dump();
}

void run_job(BakeJob& job, const LinkSolid& solid, const BakeRequest& base, int threads, bool outer,
             const FillChoice& fill) {
  const Clock::time_point start = Clock::now();
  try {
    BakeRequest request = base;
    if (job.budget) request.max_spheres = job.budget;
    request.medial.threads = threads;
    request.medial.progress = nullptr;
    const bool one = solid.parts.size() == 1;
    const TriangleMesh mesh = one ? solid.parts[0].mesh : solid.placed_mesh();
    const std::string name = one ? solid.parts[0].source : "link '" + solid.link + "'";
    const std::string sha = one ? solid.parts[0].sha256 : "";
    const MeshReport report = analyze_mesh(mesh);
    // One query (and volume, and self-intersections) for both sets; the request is
    // checked before it is built, as bake_mesh(mesh, ...) would.
    validate(request);
    const FitEvaluator fit(mesh, threads);
    const double fraction = fill.inner || (outer && fill.covers)
                                ? fill_fraction(mesh, report, request, name)
                                : std::numeric_limits<double>::quiet_NaN();
    std::optional<BakeOutcome> filled;
    if (fill.inner) filled = bake_filled_inner(mesh, report, request, name, sha, fraction);
    job.outcome = filled ? std::move(*filled) : bake_mesh(fit, report, request, name, sha);
    if (outer) {
      const Clock::time_point cover_start = Clock::now();
      job.outer = bake_outer(fit, report, request, job, name, sha, fill, fraction);
      job.outer_seconds = seconds_since(cover_start);
    }
  } catch (...) {
    job.error = std::current_exception();
  }
  job.seconds = seconds_since(start);
}

// Runs every job on `workers` threads, the largest (most triangles; ties: lower index)
// first, so that the last to finish is a small one; `done(j)` is called after job j, one
// call at a time. After a failure only jobs of a lower index than the lowest failure so far
// still run, so the lowest failing job is always known, whatever the order of completion.
void run_jobs(std::vector<BakeJob>& jobs, const std::vector<LinkSolid>& solids,
              const BakeRequest& request, bool outer, const FillChoice& fill, int workers,
              const std::function<void(std::size_t)>& done) {
  const int per_bake = std::max(1, thread_count(request.medial.threads) / workers);
  std::vector<std::size_t> order(jobs.size());
  for (std::size_t j = 0; j < order.size(); ++j) order[j] = j;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return solids[jobs[a].link].triangles() > solids[jobs[b].link].triangles();
  });
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> lowest_failed{jobs.size()};
  std::mutex report;
  auto work = [&] {
    for (std::size_t k = next++; k < order.size(); k = next++) {
      const std::size_t j = order[k];
      if (j > lowest_failed) continue;
      run_job(jobs[j], solids[jobs[j].link], request,
              workers == 1 ? request.medial.threads : per_bake, outer, fill);
      std::lock_guard<std::mutex> lock(report);
      if (jobs[j].error) lowest_failed = std::min<std::size_t>(lowest_failed, j);
      done(j);
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

LinkBakeStats link_stats(const UrdfLink& link, const LinkSolid& solid) {
  LinkBakeStats stats;
  stats.link = solid.link;
  stats.parts = solid.parts.size();
  stats.primitive_spheres = solid.spheres.size();
  stats.triangles = solid.triangles();
  stats.spheres = solid.spheres.size();
  if (solid.empty()) {
    stats.note = "no collision geometry";
  } else if (solid.parts.empty()) {
    stats.nerr = 0.0;  // the spheres are the solid
    stats.nerr_kind = "exact";
  }
  if (link.from_visual) stats.note = "visual geometry";
  return stats;
}

void fill_from_job(LinkBakeStats& stats, LinkSpheres& spheres, const LinkSolid& solid,
                   const BakeJob& job, bool own) {
  const SphereSet& baked = job.outcome.spheres;
  spheres.inner.spheres =
      solid.parts.size() == 1 ? placed(baked.spheres, solid.parts[0].origin) : baked.spheres;
  spheres.inner.spheres.insert(spheres.inner.spheres.end(), solid.spheres.begin(),
                               solid.spheres.end());
  spheres.inner.metadata_json = baked.metadata_json;
  stats.budget = job.budget;
  stats.spheres = spheres.inner.size();
  if (job.outcome.volume) {
    stats.nerr = job.outcome.volume->nerr;
    stats.nerr_kind = to_string(job.outcome.volume->kind);
  }
  stats.seconds = own ? job.seconds : 0.0;
  stats.outer_seconds = own ? job.outer_seconds : 0.0;
  const auto inner_solid = job.outcome.record.extra_strings.find(fcl::kInnerSolidKey);
  const auto fraction = job.outcome.record.extra_stats.find("shell_fraction");
  if (inner_solid != job.outcome.record.extra_strings.end() &&
      fraction != job.outcome.record.extra_stats.end()) {
    stats.inner_filled = true;
    spheres.inner_filled = true;
    stats.note += std::string(stats.note.empty() ? "" : "; ") +
                  "filled solid (a thin shell: " + number_text(fraction->second, 3) +
                  " of its volume)";
  } else if (job.outcome.solid == SolidKind::kRobust)
    stats.note += std::string(stats.note.empty() ? "" : "; ") + "robust solid" +
                  (job.outcome.robust_thickness_escalated
                       ? ", walls thickened to " + number_text(job.outcome.robust_thickness, 3) +
                             " m (thinner ones enclosed nothing)"
                       : "");
  if (!job.outer) return;
  stats.outer_filled = job.outer->record.extra_strings.count("cover_solid") > 0;
  if (stats.outer_filled)
    stats.note += std::string(stats.note.empty() ? "" : "; ") +
                  "covering set on its filled solid (a thin shell)";
  const bool one = solid.parts.size() == 1;
  const CoverResult& cover = *job.outer->cover;
  spheres.outer.spheres =
      one ? placed(cover.spheres.spheres, solid.parts[0].origin, true) : cover.spheres.spheres;
  const double gap = solid.surface_gap();
  for (Sphere& s : spheres.outer.spheres) s.radius += gap;
  spheres.outer.spheres.insert(spheres.outer.spheres.end(), solid.spheres.begin(),
                               solid.spheres.end());
  spheres.outer.metadata_json = job.outer->spheres.metadata_json;
  spheres.outer_certificate_json = outer_certificate_json(cover, one, gap);
  stats.outer_spheres = spheres.outer.size();
  stats.outer_certified = cover.certificate.certified;
  stats.outer_protrusion = cover.stats.max_protrusion + gap;
  stats.outer_start = cover.stats.start_spheres;
}

nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

std::string robot_metadata(const UrdfRobot& robot, const std::vector<LinkSolid>& solids,
                           const std::vector<LinkBakeStats>& stats, bool record_seconds) {
  nlohmann::ordered_json j;
  j["urdf"] = robot.path;
  j["generator"] = {
      {"name", "medspheres"}, {"version", MEDSPHERES_VERSION_STRING}, {"method", "medial"}};
  nlohmann::ordered_json links = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < stats.size(); ++i) {
    const LinkBakeStats& s = stats[i];
    nlohmann::ordered_json meshes = nlohmann::ordered_json::array();
    for (const LinkSolidPart& part : solids[i].parts)
      meshes.push_back({{"source", part.source}, {"sha256", part.sha256}});
    links[s.link] = {{"parts", meshes},
                     {"sphere_primitives", s.primitive_spheres},
                     {"triangles", s.triangles},
                     {"budget", s.budget ? nlohmann::ordered_json(*s.budget) : nullptr},
                     {"spheres", s.spheres},
                     {"outer_spheres", s.outer_spheres},
                     {"outer_certified", s.outer_certified},
                     {"outer_max_protrusion", number(s.outer_protrusion)},
                     {"outer_start_spheres", s.outer_start},
                     {"nerr", number(s.nerr)},
                     {"nerr_kind", s.nerr_kind},
                     {"bake_seconds", s.seconds},
                     {"baked_as", s.baked_as},
                     {"note", s.note}};
    if (!record_seconds) links[s.link].erase("bake_seconds");
    if (s.inner_filled) links[s.link][fcl::kInnerSolidKey] = fcl::kInnerSolidFilled;
    if (s.outer_filled) links[s.link]["cover_solid"] = "filled";
  }
  j["links"] = links;
  return j.dump();
}

// The spheres link \p solid's cover starts from (options.outer_start), or nullptr; they are
// checked as tighten_cover would.
const std::vector<Sphere>* outer_start_of(const RobotBakeOptions& options, const LinkSolid& solid,
                                          const std::string& source) {
  const auto it = options.outer_start.find(solid.link);
  if (it == options.outer_start.end() || solid.parts.empty()) return nullptr;
  if (!options.outer)
    throw InputError(source, "link '" + solid.link +
                                 "': an outer set's start is given, but no outer sets are baked");
  const std::string problem = cover_start_problem(it->second);
  if (!problem.empty())
    throw InputError(source, "link '" + solid.link + "': outer set's start: " + problem);
  return &it->second;
}

// Link-frame spheres in the frame the link is baked in (run_job): its one part's, or the
// link's own for several parts; each radius grown by the rounding of the move (placed).
std::vector<Sphere> start_in_bake_frame(const std::vector<Sphere>& start, const LinkSolid& solid) {
  if (solid.parts.size() != 1) return start;
  return placed(start, solid.parts[0].origin.inverse(), true);
}

// Link \p solid's weights (options.outer_weights), or nullptr (none, or no meshed parts).
const ProtrusionWeights* outer_weights_of(const RobotBakeOptions& options, const LinkSolid& solid) {
  const auto it = options.outer_weights.find(solid.link);
  return it == options.outer_weights.end() || solid.parts.empty() ? nullptr : &it->second;
}

// Link-frame weights in the frame the link is baked in (as start_in_bake_frame).
ProtrusionWeights weights_in_bake_frame(const ProtrusionWeights& w, const LinkSolid& solid) {
  if (solid.parts.size() != 1) return w;
  ProtrusionWeights out = w;
  const Eigen::Isometry3d X_GL = solid.parts[0].origin.inverse();
  for (Eigen::Vector3d& p : out.points) p = X_GL * p;
  return out;
}

std::vector<std::string> unused_outer_start(const RobotBakeOptions& options,
                                            const std::vector<LinkSolid>& solids) {
  std::vector<std::string> unused;
  for (const auto& entry : options.outer_start)
    if (std::none_of(solids.begin(), solids.end(),
                     [&](const LinkSolid& s) { return s.link == entry.first && !s.parts.empty(); }))
      unused.push_back(entry.first);
  return unused;
}

// A link of sphere primitives alone: they are its inner set and, with outer sets, their
// own exact cover.
void fill_primitive_link(const LinkSolid& solid, bool outer, LinkBakeStats& stats,
                         LinkSpheres& sets) {
  sets.inner.spheres = solid.spheres;
  if (!outer || solid.spheres.empty()) return;
  sets.outer.spheres = solid.spheres;
  sets.outer_certificate_json =
      R"({"certified":true,"surface_covered":true,"interior_certified":true,)"
      R"("sphere_primitives":true})";
  stats.outer_spheres = solid.spheres.size();
  stats.outer_certified = true;
  stats.outer_protrusion = 0.0;
}

// The bake job of link i (solids[i] with parts), shared with an earlier link whose bake
// computes the same, else added to jobs; returns its index.
std::size_t job_for_link(std::size_t i, const std::vector<LinkSolid>& solids,
                         const std::vector<std::optional<std::size_t>>& budgets,
                         const RobotBakeOptions& options, const std::string& urdf_path,
                         std::vector<BakeJob>& jobs,
                         std::map<std::string, std::size_t>& job_by_key) {
  const std::vector<Sphere>* given = outer_start_of(options, solids[i], urdf_path);
  const ProtrusionWeights* weights = given ? nullptr : outer_weights_of(options, solids[i]);
  // A link whose cover starts from its own spheres or has its own weights shares no bake.
  const std::string key = job_key(solids[i], budgets[i]) +
                          (given ? " start of " + solids[i].link : "") +
                          (weights ? " weights of " + solids[i].link : "");
  const auto [it, fresh] = job_by_key.emplace(key, jobs.size());
  if (fresh) {
    jobs.push_back(BakeJob{i, budgets[i], {}, std::nullopt, {}, {}, 0.0, 0.0, nullptr});
    if (given) jobs.back().outer_start = start_in_bake_frame(*given, solids[i]);
    if (weights) jobs.back().outer_weights = weights_in_bake_frame(*weights, solids[i]);
  }
  return it->second;
}

// Throws the error of the first failed job (in link order), naming its link.
void rethrow_first_error(const std::vector<BakeJob>& jobs, const std::vector<LinkSolid>& solids,
                         const std::string& urdf_path) {
  for (const BakeJob& job : jobs) {
    if (!job.error) continue;
    const std::string link = "link '" + solids[job.link].link + "': ";
    try {
      std::rethrow_exception(job.error);
    } catch (const InputError& e) {
      throw InputError(urdf_path, link + e.what());
    } catch (const std::invalid_argument& e) {
      throw InputError(urdf_path, link + e.what());
    } catch (const std::exception& e) {
      throw Error(urdf_path + ": " + link + e.what());
    }
  }
}

}  // namespace

RobotBakeResult bake_robot(const UrdfRobot& robot, const std::vector<LinkSolid>& solids,
                           const RobotBakeOptions& options) {
  const Clock::time_point start = Clock::now();
  if (solids.size() != robot.links.size() || robot.model.links.size() != robot.links.size())
    throw std::invalid_argument("bake_robot: one solid and one model link per link are needed");
  check_threads_option(options.jobs, "jobs");
  validate(options.request);
  const std::vector<std::optional<std::size_t>> budgets =
      link_bake_budgets(solids, options.budget, robot.path);

  RobotBakeResult result;
  result.model = robot.model;
  result.unused_outer_start = unused_outer_start(options, solids);
  std::vector<BakeJob> jobs;
  std::vector<std::size_t> job_of(solids.size(), std::numeric_limits<std::size_t>::max());
  std::map<std::string, std::size_t> job_by_key;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    result.links.push_back(link_stats(robot.links[i], solids[i]));
    result.model.links[i].note = result.links[i].note;
    if (solids[i].parts.empty()) {
      fill_primitive_link(solids[i], options.outer, result.links[i], result.model.links[i].spheres);
      if (options.progress) options.progress(result.links[i]);
      continue;
    }
    job_of[i] = job_for_link(i, solids, budgets, options, robot.path, jobs, job_by_key);
  }

  auto finish_links = [&](std::size_t j) {
    if (jobs[j].error) return;
    for (std::size_t i = jobs[j].link; i < solids.size(); ++i) {
      if (job_of[i] != j) continue;
      const bool own = i == jobs[j].link;
      fill_from_job(result.links[i], result.model.links[i].spheres, solids[i], jobs[j], own);
      if (!own) result.links[i].baked_as = solids[jobs[j].link].link;
      if (options.progress) options.progress(result.links[i]);
    }
  };
  const int workers = static_cast<int>(
      std::min<std::size_t>(jobs.size(), static_cast<std::size_t>(thread_count(options.jobs))));
  const FillChoice fill{options.fill_thin_shells, options.fill_thin_shell_covers,
                        options.fill_cover_resolution};
  run_jobs(jobs, solids, options.request, options.outer, fill, std::max(1, workers), finish_links);
  rethrow_first_error(jobs, solids, robot.path);
  result.model.metadata_json =
      robot_metadata(robot, solids, result.links, options.request.record_seconds);
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace medspheres
