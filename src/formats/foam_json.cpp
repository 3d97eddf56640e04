#include "medspheres/formats/foam_json.h"

#include <cerrno>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "medspheres/error.h"

namespace medspheres::formats {

using Json = nlohmann::ordered_json;

namespace {

Json parse_json(const std::string& text, const std::string& source) {
  try {
    return Json::parse(text);
  } catch (const Json::exception& e) {
    throw InputError(source, std::string("not valid JSON: ") + e.what());
  }
}

Json level_json(const std::vector<Sphere>& spheres) {
  Json list = Json::array();
  for (const Sphere& s : spheres)
    list.push_back({{"origin", {s.center.x(), s.center.y(), s.center.z()}}, {"radius", s.radius}});
  return {{"mean", nullptr}, {"best", nullptr}, {"worst", nullptr}, {"spheres", std::move(list)}};
}

std::optional<double> optional_number(const Json& level, const char* key, const std::string& source,
                                      const std::string& where) {
  if (!level.contains(key) || level.at(key).is_null()) return std::nullopt;
  if (!level.at(key).is_number())
    throw InputError(source, where + ": \"" + key + "\" is not a number");
  return level.at(key).get<double>();
}

FoamLevel read_level(const Json& level, const std::string& source, const std::string& where) {
  if (!level.is_object() || !level.contains("spheres") || !level.at("spheres").is_array())
    throw InputError(source, where + " is not an object with a \"spheres\" list");
  FoamLevel out;
  out.mean = optional_number(level, "mean", source, where);
  out.best = optional_number(level, "best", source, where);
  out.worst = optional_number(level, "worst", source, where);
  const Json& list = level.at("spheres");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Json& s = list[i];
    const std::string at = where + " sphere " + std::to_string(i);
    if (!s.is_object() || !s.contains("origin") || !s.contains("radius") ||
        !s.at("origin").is_array() || s.at("origin").size() != 3 || !s.at("radius").is_number())
      throw InputError(source, at + " is not {\"origin\": [x, y, z], \"radius\": r}: " + s.dump());
    for (const Json& x : s.at("origin"))
      if (!x.is_number()) throw InputError(source, at + ": the origin holds " + x.dump());
    const Json& o = s.at("origin");
    out.spheres.push_back({{o[0].get<double>(), o[1].get<double>(), o[2].get<double>()},
                           s.at("radius").get<double>()});
  }
  SphereSet set;
  set.spheres = out.spheres;
  try {
    validate_sphere_set(set, source);
  } catch (const InputError& e) {
    throw InputError(source, where + ": " + e.problem());
  }
  return out;
}

// The numeric value of a database key ("8"), for picking the largest.
long key_number(const std::string& key, const std::string& source, const std::string& where) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(key.c_str(), &end, 10);
  if (key.empty() || *end != '\0' || errno != 0)
    throw InputError(source, where + ": the key \"" + key + "\" is not a whole number");
  return v;
}

// The entry with the largest numeric key of a {"<n>": value} object.
const Json& largest_key(const Json& o, const std::string& source, const std::string& where) {
  if (!o.is_object() || o.empty())
    throw InputError(source, where + " is not a non-empty object keyed by numbers");
  auto best = o.begin();
  for (auto it = o.begin(); it != o.end(); ++it)
    if (key_number(it.key(), source, where) > key_number(best.key(), source, where)) best = it;
  return *best;
}

}  // namespace

std::string foam_mesh_json(const std::vector<Sphere>& spheres) {
  SphereSet set;
  set.spheres = spheres;
  validate_sphere_set(set, "foam JSON");
  return Json::array({level_json(spheres)}).dump(4) + "\n";
}

std::vector<FoamLevel> parse_foam_mesh_json(const std::string& text, const std::string& source) {
  const Json doc = parse_json(text, source);
  if (!doc.is_array() || doc.empty())
    throw InputError(source, "not a foam sphere file: expected a non-empty list of levels");
  std::vector<FoamLevel> levels;
  for (std::size_t i = 0; i < doc.size(); ++i)
    levels.push_back(read_level(doc[i], source, "level " + std::to_string(i)));
  return levels;
}

std::string foam_robot_json(const RobotSpheres& spheres) {
  validate_robot_spheres(spheres, "foam JSON");
  Json db = Json::object();
  for (const LinkSphereList& l : spheres)
    db[l.link] = {{std::to_string(l.spheres.size()), {{"1", level_json(l.spheres)}}}};
  return db.dump(4) + "\n";
}

RobotSpheres parse_foam_robot_json(const std::string& text, const std::string& source) {
  const Json doc = parse_json(text, source);
  if (!doc.is_object()) throw InputError(source, "not a foam sphere database: expected an object");
  RobotSpheres out;
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    const std::string link = it.key().substr(0, it.key().find("::"));
    const std::string where = "\"" + it.key() + "\"";
    const Json& branch = largest_key(it.value(), source, where);
    const Json& level = largest_key(branch, source, where);
    const FoamLevel read = read_level(level, source, "link " + where);
    LinkSphereList* entry = nullptr;
    for (LinkSphereList& l : out)
      if (l.link == link) entry = &l;
    if (!entry) entry = &out.emplace_back(LinkSphereList{link, {}});
    entry->spheres.insert(entry->spheres.end(), read.spheres.begin(), read.spheres.end());
  }
  validate_robot_spheres(out, source);
  return out;
}

bool is_foam_robot_json(const std::string& text) {
  const Json doc = Json::parse(text, nullptr, false);
  return doc.is_object();
}

}  // namespace medspheres::formats
