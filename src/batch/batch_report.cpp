// The report of a batch bake: one row per input, as JSON or CSV.
#include <cmath>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "medspheres/batch/batch.h"
#include "medspheres/number_text.h"

namespace medspheres {

namespace {

// RFC 4180: a field with a comma, a quote or a line break is quoted, quotes doubled.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// The robot columns of the planner summary, in order: each null for a row without one. The
// one list the JSON rows, the CSV header and the CSV rows read.
nlohmann::ordered_json planner_fields(const std::optional<BatchPlannerSummary>& s) {
  using Json = nlohmann::ordered_json;
  return {{"default_from", s ? Json(s->default_from) : Json()},
          {"checked_pairs", s ? Json(s->checked_pairs) : Json()},
          {"estimate_samples", s ? Json(s->estimate_samples) : Json()},
          {"false_positives", s ? Json(s->false_positives) : Json()},
          {"false_negatives", s ? Json(s->false_negatives) : Json()}};
}

std::string planner_csv_header() {
  std::string out;
  const nlohmann::ordered_json fields = planner_fields(std::nullopt);
  for (const auto& field : fields.items()) out += field.key() + ",";
  return out;
}

// The fields of planner_fields as CSV, each followed by a comma (a null one empty).
std::string planner_csv(const std::optional<BatchPlannerSummary>& s) {
  std::string out;
  const nlohmann::ordered_json fields = planner_fields(s);
  for (const auto& field : fields.items()) {
    const auto& v = field.value();
    out += (v.is_null() ? "" : v.is_string() ? csv_field(v.get<std::string>()) : v.dump()) + ",";
  }
  return out;
}

}  // namespace

std::string batch_report_json(const BatchResult& result) {
  using Json = nlohmann::ordered_json;
  const bool robots = result.items == BatchItems::kRobots;
  Json rows = Json::array();
  for (const BatchRow& r : result.rows) {
    Json row = {{"input", r.input.path},
                {"relative", r.input.relative},
                {"output", r.output},
                {"outcome", to_string(r.outcome)}};
    if (robots) row["links"] = r.links;
    row["spheres"] = r.spheres;
    if (robots) row.update(planner_fields(r.planner));
    if (!robots) row["nerr"] = std::isfinite(r.nerr) ? Json(r.nerr) : Json();
    row["seconds"] = r.seconds;
    row["error"] = r.error.empty() ? Json() : Json(r.error);
    rows.push_back(std::move(row));
  }
  const Json totals = {{"baked", result.count(BatchOutcome::kBaked)},
                       {"cached", result.count(BatchOutcome::kCached)},
                       {"failed", result.count(BatchOutcome::kFailed)},
                       {"other_shards", result.other_shards},
                       {"seconds", result.seconds}};
  return Json{{"rows", rows}, {"totals", totals}}.dump(2) + "\n";
}

std::string batch_report_csv(const BatchResult& result) {
  const bool robots = result.items == BatchItems::kRobots;
  std::string out = robots ? "input,relative,output,outcome,links,spheres," + planner_csv_header() +
                                 "seconds,error\r\n"
                           : "input,relative,output,outcome,spheres,nerr,seconds,error\r\n";
  for (const BatchRow& r : result.rows) {
    out += csv_field(r.input.path) + "," + csv_field(r.input.relative) + "," + csv_field(r.output) +
           "," + to_string(r.outcome) + ",";
    if (robots) out += std::to_string(r.links) + ",";
    out += std::to_string(r.spheres) + ",";
    if (robots) out += planner_csv(r.planner);
    if (!robots) out += (std::isfinite(r.nerr) ? exact_number_text(r.nerr) : "") + ",";
    out += exact_number_text(r.seconds) + "," + csv_field(r.error) + "\r\n";
  }
  return out;
}

}  // namespace medspheres
