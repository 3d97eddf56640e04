// The self-collision report (self_collision_report.h).
#include "medspheres/formats/self_collision_report.h"

#include <algorithm>

#include "medspheres/formats/planner_options.h"
#include "medspheres/number_text.h"

namespace medspheres::formats {

namespace {

std::string pad(const std::string& text, std::size_t width) {
  return text.size() >= width ? text + " " : text + std::string(width - text.size(), ' ');
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

}  // namespace

std::map<PairClass, std::pair<std::size_t, std::size_t>> pair_class_counts(
    const SelfCollisionMatrix& m) {
  std::map<PairClass, std::pair<std::size_t, std::size_t>> out;
  for (const LinkPairClass& p : m.pairs) {
    ++out[p.kind].first;
    if (p.ignored) ++out[p.kind].second;
  }
  return out;
}

std::string self_collision_report(const RobotModel& model, const RobotSpheres& spheres) {
  const PlannerSetup s = planner_setup_for(model, spheres);
  std::string t = "self-collision matrix of " + (model.name.empty() ? "robot" : model.name) + "\n";
  const SelfCollisionMatrix m = s.self_collision.value_or(SelfCollisionMatrix{});
  if (!m.srdf.empty()) t += "skipped pairs also taken from " + m.srdf + "\n";
  if (m.samples > 0)
    t += std::to_string(m.samples) + " samples (seed " + std::to_string(m.seed) +
         "); always: the meshes collide in at least " + number_text(100 * m.threshold, 4) +
         "% of them; never: the meshes never within " + number_text(m.margin, 4) + " m\n";
  else
    t += "not sampled: only adjacent pairs skipped\n";
  t += "tool frames: " + joined(s.tool_frames) + " (" + tool_frames_from_text(s.tool_frames_from) +
       ")\n";
  t += "locked joints: " + joined(s.locked_joints) + "\n";
  t += "default configuration: " + default_from_text(s.default_from) + "\n";
  for (const auto& [joint, q] : s.default_positions)
    t += "  " + joint + " = " + number_text(q, 6) + "\n";
  t += "\n" + pad("class", 13) + pad("pairs", 7) + "skipped\n";
  std::size_t total = 0, skipped = 0;
  for (const auto& [kind, n] : pair_class_counts(m)) {
    t += pad(pair_class_name(kind), 13) + pad(std::to_string(n.first), 7) +
         std::to_string(n.second) + "\n";
    total += n.first;
    skipped += n.second;
  }
  t += pad("total", 13) + pad(std::to_string(total), 7) + std::to_string(skipped) + "\n";
  t += "sphere pairs cuRobo checks: " + std::to_string(curobo_sphere_pairs(model, spheres)) +
       " (each sphere of a link against each sphere of a partner its files do not skip)\n\n";
  std::size_t width = 6;
  for (const LinkPairClass& p : m.pairs) width = std::max(width, p.link1.size() + 2);
  t += pad("link1", width) + pad("link2", width) + pad("class", 13) + "planner\n";
  for (const LinkPairClass& p : m.pairs)
    t += pad(p.link1, width) + pad(p.link2, width) + pad(pair_class_name(p.kind), 13) +
         (p.ignored ? "skips" : "checks") + (p.reason.empty() ? "" : " (" + p.reason + ")") + "\n";
  bool any_buffer = false;
  for (const auto& [link, b] : m.buffer) any_buffer = any_buffer || b != 0.0;
  if (any_buffer) {
    t += "\nself-collision buffers (m, added to the link's radii in self-collision only)\n";
    for (const auto& [link, b] : m.buffer)
      if (b != 0.0) t += "  " + link + " " + number_text(b, 6) + "\n";
  }
  return t;
}

}  // namespace medspheres::formats
