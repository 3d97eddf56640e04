// Baking robots from URDF files: one into its folder, many on the batch driver, cached.
#include "medspheres/batch/batch_robot.h"

#include <filesystem>
#include <map>
#include <set>
#include <utility>

#include <nlohmann/json.hpp>

#include "batch_driver.h"
#include "medspheres/batch/batch_cache.h"
#include "medspheres/error.h"
#include "medspheres/formats/curobo_yaml.h"
#include "medspheres/formats/robot_spheres.h"
#include "medspheres/formats/sphere_document.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/number_text.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot_bake/robot_warnings.h"
#include "medspheres/robot_file.h"
#include "medspheres/sha256.h"
#include "medspheres/version.h"

namespace medspheres {

namespace fs = std::filesystem;

namespace {

// The cache entry's file suffix.
const char* const kEntrySuffix = ".robot.msgpack";

const std::vector<formats::SphereFormat>& chosen_formats(const RobotJob& job) {
  return job.formats.empty() ? formats::robot_formats() : job.formats;
}

std::size_t planner_spheres(const RobotModel& model, formats::SphereChoice choice) {
  std::size_t n = 0;
  for (const formats::LinkSphereList& l : formats::robot_spheres(model, choice))
    n += l.spheres.size();
  return n;
}

// What the row reports of \p r's planner files: none without a planner setup.
std::optional<BatchPlannerSummary> planner_summary(const RobotFileResult& r) {
  if (!r.bake.model.planner) return std::nullopt;
  const PlannerSetup& setup = *r.bake.model.planner;
  BatchPlannerSummary s;
  s.default_from = setup.default_from;
  if (setup.self_collision)
    for (const LinkPairClass& p : setup.self_collision->pairs) s.checked_pairs += !p.ignored;
  s.estimate_samples = r.planner.estimate.samples;
  s.false_positives = r.planner.estimate.false_positives;
  s.false_negatives = r.planner.estimate.false_negatives;
  return s;
}

nlohmann::json summary_json(const std::optional<BatchPlannerSummary>& s) {
  if (!s) return nullptr;
  return {{"default_from", s->default_from},
          {"checked_pairs", s->checked_pairs},
          {"estimate_samples", s->estimate_samples},
          {"false_positives", s->false_positives},
          {"false_negatives", s->false_negatives}};
}

std::optional<BatchPlannerSummary> summary_of(const nlohmann::json& j) {
  if (j.is_null()) return std::nullopt;
  BatchPlannerSummary s;
  s.default_from = j.at("default_from").get<std::string>();
  s.checked_pairs = j.at("checked_pairs").get<std::size_t>();
  s.estimate_samples = j.at("estimate_samples").get<std::size_t>();
  s.false_positives = j.at("false_positives").get<std::size_t>();
  s.false_negatives = j.at("false_negatives").get<std::size_t>();
  return s;
}

// The files \p robot's bake reads before its folder \p out is replaced must lie outside it.
void check_output_spares(const UrdfRobot& robot, const std::string& out, const RobotJob& job) {
  std::vector<std::string> inputs = robot_input_files(robot);
  inputs.push_back(job.planner.srdf);
  check_output_spares_inputs(out, inputs);
}

// A robot read and baked into \p out; its files are kept in \p files.
RobotFileResult bake_read_robot(const UrdfRobot& robot, const std::string& out, const RobotJob& job,
                                std::map<std::string, std::string>& files) {
  check_planner_request(robot.model, job.planner);
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  RobotFileResult r;
  r.warnings = robot_warnings(robot, job.read.from_visual);
  r.bake = bake_robot(robot, solids, job.bake);
  if (job.contact && job.planner.sample && job.bake.outer) {
    RobotBakeOptions again = job.bake;
    again.progress = nullptr;
    PlannerRequest planner = job.planner;
    planner.self_collision.threads = job.bake.jobs;
    r.bake = rebake_contact_aware(robot, solids, again, r.bake,
                                  formats::robot_output_choice(job.set, r.bake.model), planner,
                                  *job.contact);
  }
  if (!job.options_json.empty()) {
    nlohmann::ordered_json meta = nlohmann::ordered_json::parse(r.bake.model.metadata_json);
    meta["options"] = nlohmann::ordered_json::parse(job.options_json);
    r.bake.model.metadata_json = meta.dump();
  }
  r.choice = formats::robot_output_choice(job.set, r.bake.model);
  r.spheres = planner_spheres(r.bake.model, r.choice);
  PlannerRequest planner = job.planner;
  planner.self_collision.threads = job.bake.jobs;
  r.bake.model.planner = make_planner_setup(r.bake.model, solids, r.choice, planner, &r.planner);
  files = formats::robot_output_files(chosen_formats(job), r.bake.model, r.choice, robot.path);
  formats::write_output_folder(out, files);
  return r;
}

// The cache's name of \p path (a file \p robot reads: a mesh) when the URDF's relative path
// is \p relative: its path relative to the URDF's folder, below \p relative's folder. A copy
// of the folders keeps it.
std::string layout_path(const UrdfRobot& robot, const std::string& relative,
                        const std::string& path) {
  const fs::path urdf_dir = fs::absolute(robot.path).lexically_normal().parent_path();
  const fs::path from_urdf = fs::absolute(path).lexically_normal().lexically_relative(urdf_dir);
  return (fs::path(relative).parent_path() / from_urdf).lexically_normal().generic_string();
}

// The path as read -> the cache's name, of the URDF and each mesh file of \p robot.
std::map<std::string, std::string> cache_names(const UrdfRobot& robot,
                                               const std::string& relative) {
  std::map<std::string, std::string> names = {{robot.path, relative}};
  for (const UrdfLink& link : robot.links)
    for (const LinkPart& part : link.parts)
      if (part.shape == PartShape::kMesh)
        names[part.path] = layout_path(robot, relative, part.path);
  return names;
}

std::map<std::string, std::string> inverse(const std::map<std::string, std::string>& names) {
  std::map<std::string, std::string> out;
  for (const auto& [from, to] : names) out[to] = from;
  return out;
}

// \p files with the paths their robot file records (metadata "urdf" and each part's
// "source", robot_bake.h) and the cuRobo configurations' urdf_path renamed by \p names;
// what names does not hold is kept. The other files record no path.
std::map<std::string, std::string> renamed(std::map<std::string, std::string> files,
                                           const std::map<std::string, std::string>& names) {
  auto rename = [&names](nlohmann::ordered_json& value) {
    if (!value.is_string()) return;
    const auto it = names.find(value.get<std::string>());
    if (it != names.end()) value = it->second;
  };
  const auto ends_with = [](const std::string& name, const std::string& suffix) {
    return name.size() >= suffix.size() &&
           name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  for (auto& [name, text] : files) {
    if (ends_with(name, ".curobo.yml") || ends_with(name, ".curobo_v1.yml"))
      text = formats::curobo_yaml_with_urdf_path(text, names, name);
    if (!ends_with(name, ".robot.json")) continue;
    nlohmann::ordered_json meta = nlohmann::ordered_json::parse(robot_json_metadata(text, name));
    if (meta.contains("urdf")) rename(meta["urdf"]);
    if (meta.contains("links") && meta["links"].is_object())
      for (auto& [link, entry] : meta["links"].items())
        if (entry.contains("parts") && entry["parts"].is_array())
          for (auto& part : entry["parts"])
            if (part.is_object() && part.contains("source")) rename(part["source"]);
    text = robot_json_with_metadata(text, meta.dump(), name);
  }
  return files;
}

std::string budget_text(const RobotBudget& b) {
  std::string t = "per_link=" + (b.per_link ? std::to_string(*b.per_link) : "none") +
                  "\ntotal=" + (b.total ? std::to_string(*b.total) : "none") + "\n";
  for (const auto& [link, k] : b.links) t += "link " + link + "=" + std::to_string(k) + "\n";
  return t;
}

// The entry's files, their paths named as read (\p names: cache name -> path), written
// into \p out, and the row's counts; false when the entry does not read as one (it is then
// baked again).
bool copy_entry(const std::string& bytes, const std::map<std::string, std::string>& names,
                const std::string& out, BatchRow& row) {
  std::map<std::string, std::string> files;
  std::size_t links = 0, spheres = 0;
  std::optional<BatchPlannerSummary> planner;
  try {
    const nlohmann::json entry = nlohmann::json::from_msgpack(bytes);
    links = entry.at("links").get<std::size_t>();
    spheres = entry.at("spheres").get<std::size_t>();
    planner = summary_of(entry.at("planner"));
    for (const auto& [name, data] : entry.at("files").items()) {
      const std::vector<std::uint8_t>& b = data.get_binary();
      files[name] = std::string(b.begin(), b.end());
    }
    files = renamed(std::move(files), names);
  } catch (const nlohmann::json::exception&) {
    return false;
  } catch (const InputError&) {
    return false;
  }
  formats::write_output_folder(out, files);
  row.links = links;
  row.spheres = spheres;
  row.planner = std::move(planner);
  return true;
}

std::string entry_bytes(const std::map<std::string, std::string>& files, const BatchRow& row) {
  nlohmann::json entry = {
      {"links", row.links}, {"spheres", row.spheres}, {"planner", summary_json(row.planner)}};
  nlohmann::json all = nlohmann::json::object();
  for (const auto& [name, text] : files)
    all[name] = nlohmann::json::binary(std::vector<std::uint8_t>(text.begin(), text.end()));
  entry["files"] = std::move(all);
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_msgpack(entry);
  return std::string(bytes.begin(), bytes.end());
}

// One URDF: from the cache, or read, baked, written and stored. Throws on failure. The
// entry names the files the robot reads by their relative layout (cache_names), so that a
// copy of the folders elsewhere finds it; its files get their paths as read again.
void bake_robot_input(const RobotJob& job, const BakeCache* cache, BatchRow& row) {
  const std::string urdf_sha = file_sha256(row.input.path);
  const UrdfRobot robot = read_urdf(row.input.path, job.read);
  check_output_spares(robot, row.output, job);
  row.warnings = robot_warnings(robot, job.read.from_visual);
  std::string key;
  if (cache) {
    key = robot_cache_key(robot, urdf_sha, job, row.input.relative);
    const std::optional<std::string> hit = cache->find_bytes(key, kEntrySuffix);
    if (hit && copy_entry(*hit, inverse(cache_names(robot, row.input.relative)), row.output, row)) {
      row.outcome = BatchOutcome::kCached;
      return;
    }
  }
  std::map<std::string, std::string> files;
  const RobotFileResult r = bake_read_robot(robot, row.output, job, files);
  row.links = r.bake.links.size();
  row.spheres = r.spheres;
  row.planner = planner_summary(r);
  if (cache)
    cache->store_bytes(key, kEntrySuffix,
                       entry_bytes(renamed(files, cache_names(robot, row.input.relative)), row));
  row.outcome = BatchOutcome::kBaked;
}

}  // namespace

RobotFileResult bake_robot_file(const std::string& urdf, const std::string& out,
                                const RobotJob& job) {
  std::map<std::string, std::string> files;
  const UrdfRobot robot = read_urdf(urdf, job.read);
  check_output_spares(robot, out, job);
  return bake_read_robot(robot, out, job, files);
}

std::string robot_output_relative(const std::string& relative) {
  const fs::path p(relative);
  return (p.parent_path() / p.stem()).generic_string();
}

std::string robot_cache_key(const UrdfRobot& robot, const std::string& urdf_sha256,
                            const RobotJob& job, const std::string& relative) {
  std::string t = std::string("medspheres robot cache 2\nversion=") + MEDSPHERES_VERSION_STRING +
                  "\nrevision=" + std::to_string(MEDSPHERES_OUTPUT_REVISION) +
                  "\nurdf=" + relative + " " + urdf_sha256 + "\n";
  std::set<std::string> hashed;
  for (const UrdfLink& link : robot.links)
    for (const LinkPart& part : link.parts) {
      if (part.shape != PartShape::kMesh || !hashed.insert(part.path).second) continue;
      try {
        t +=
            "mesh=" + layout_path(robot, relative, part.path) + " " + file_sha256(part.path) + "\n";
      } catch (const InputError& e) {
        throw InputError(robot.path, "link '" + link.name + "': " + e.what());
      }
    }
  t += bake_request_text(job.bake.request) + budget_text(job.bake.budget);
  for (const auto& [link, spheres] : job.bake.outer_start)
    t += "outer_start=" + link + " " + spheres_text(spheres) + "\n";
  t += std::string("outer=") + (job.bake.outer ? "1" : "0") +
       "\nfill=" + (job.bake.fill_thin_shells ? "1" : "0") +
       (job.bake.fill_thin_shell_covers
            ? "\nfill_covers=" + std::to_string(job.bake.fill_cover_resolution)
            : std::string()) +
       "\nfrom_visual=" + (job.read.from_visual ? "1" : "0") + "\nformats=";
  for (formats::SphereFormat f : chosen_formats(job))
    t += std::string(formats::sphere_format_name(f)) + ",";
  t += "\nset=" + std::string(!job.set                                    ? "auto"
                              : *job.set == formats::SphereChoice::kInner ? "inner"
                                                                          : "outer");
  t += "\n" + planner_request_text(job.planner);
  if (job.contact)
    t += "contact=" + std::to_string(job.contact->samples) + " " +
         std::to_string(job.contact->seed) + " " + exact_number_text(job.contact->band) + " " +
         exact_number_text(job.contact->weight) + " " + exact_number_text(job.contact->min_share) +
         "\n";
  if (!job.planner.srdf.empty()) t += "srdf_sha256=" + file_sha256(job.planner.srdf) + "\n";
  return sha256_hex(t + "\noptions=" + job.options_json + "\n");
}

BatchResult bake_robot_batch(const std::vector<BatchInput>& inputs,
                             const RobotBatchOptions& options) {
  RobotJob job = options.robot;
  job.bake.request = batch_request(job.bake.request, options.jobs);
  job.bake.jobs = batch_threads_each(options.jobs);
  job.bake.progress = nullptr;
  auto run = [&job](BatchRow& row, const BakeCache* cache) { bake_robot_input(job, cache, row); };
  return run_batch(inputs, options, {BatchItems::kRobots, robot_output_relative, run});
}

}  // namespace medspheres
