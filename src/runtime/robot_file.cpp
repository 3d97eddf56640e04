#include "medspheres/robot_file.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/io.h"

namespace medspheres {

using Json = nlohmann::ordered_json;

namespace {

// Reads typed values out of one JSON object, naming the file and the object ("joint
// "j1"") in every error.
class Reader {
 public:
  Reader(const Json& object, std::string source, std::string where)
      : o_(object), source_(std::move(source)), where_(std::move(where)) {
    if (!o_.is_object()) fail("is not a JSON object");
  }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(source_, where_ + ": " + problem);
  }
  bool has(const char* key) const { return o_.contains(key) && !o_.at(key).is_null(); }
  const Json& at(const char* key) const {
    if (!o_.contains(key)) fail(std::string("missing the key \"") + key + "\"");
    return o_.at(key);
  }
  std::string text(const char* key, bool required = true) const {
    if (!required && !has(key)) return "";
    const Json& v = at(key);
    if (!v.is_string()) fail(std::string("\"") + key + "\" is not a string: " + v.dump());
    return v.get<std::string>();
  }
  double number(const char* key, double fallback) const {
    if (!has(key)) return fallback;
    const Json& v = at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      fail(std::string("\"") + key + "\" is not a finite number: " + v.dump());
    return v.get<double>();
  }
  template <std::size_t N>
  std::array<double, N> numbers(const char* key) const {
    const Json& v = at(key);
    if (!v.is_array() || v.size() != N)
      fail(std::string("\"") + key + "\" is not a list of " + std::to_string(N) +
           " numbers: " + v.dump());
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
        fail(std::string("\"") + key +
             "\" holds a value that is not a finite number: " + v[i].dump());
      out[i] = v[i].get<double>();
    }
    return out;
  }
  const std::string& where() const { return where_; }

 private:
  const Json& o_;
  std::string source_;
  std::string where_;
};

SphereSet read_spheres(const Reader& r, const char* key) {
  SphereSet set;
  if (!r.has(key)) return set;
  const Json& v = r.at(key);
  if (!v.is_array()) r.fail(std::string("\"") + key + "\" is not a list of spheres");
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Json& s = v[i];
    if (!s.is_array() || s.size() != 4)
      r.fail(std::string("\"") + key + "\" sphere " + std::to_string(i) +
             " is not [x, y, z, r]: " + s.dump());
    for (const Json& x : s)
      if (!x.is_number())
        r.fail(std::string("\"") + key + "\" sphere " + std::to_string(i) +
               " holds a value that is not a number: " + s.dump());
    set.spheres.push_back(
        {{s[0].get<double>(), s[1].get<double>(), s[2].get<double>()}, s[3].get<double>()});
  }
  return set;  // checked with the whole model
}

Link read_link(const Json& j, std::size_t index, const std::string& source) {
  const Reader first(j, source, "link " + std::to_string(index));
  Link link;
  link.name = first.text("name");
  const Reader r(j, source, "link \"" + link.name + "\"");
  link.spheres.inner = read_spheres(r, "inner");
  link.spheres.outer = read_spheres(r, "outer");
  if (r.has("outer_certificate")) {
    if (!r.at("outer_certificate").is_object())
      r.fail("\"outer_certificate\" is not a JSON object");
    link.spheres.outer_certificate_json = r.at("outer_certificate").dump();
  }
  if (r.has("inner_solid")) {
    const std::string solid = r.text("inner_solid");
    if (solid != "filled")
      r.fail("\"inner_solid\" is \"" + solid + "\"; the only value is \"filled\"");
    link.spheres.inner_filled = true;
  }
  link.note = r.text("note", false);
  return link;
}

JointType read_joint_type(const Reader& r) {
  const std::string t = r.text("type");
  for (JointType k :
       {JointType::kFixed, JointType::kRevolute, JointType::kContinuous, JointType::kPrismatic})
    if (t == joint_type_name(k)) return k;
  r.fail("unknown joint type \"" + t + "\" (fixed, revolute, continuous or prismatic)");
}

Eigen::Isometry3d read_origin(const Reader& joint, const std::string& source) {
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  if (!joint.has("origin")) return x;
  const Reader r(joint.at("origin"), source, joint.where() + " origin");
  if (r.has("xyz")) {
    const auto p = r.numbers<3>("xyz");
    x.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  }
  if (r.has("quaternion_xyzw") && r.has("rpy"))
    r.fail("gives both \"quaternion_xyzw\" and \"rpy\"");
  if (r.has("quaternion_xyzw")) {
    const auto q = r.numbers<4>("quaternion_xyzw");
    const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
    if (std::abs(quat.norm() - 1.0) > 1e-6)
      r.fail("\"quaternion_xyzw\" is not a unit quaternion (norm " + std::to_string(quat.norm()) +
             ")");
    x.linear() = quat.normalized().toRotationMatrix();
  } else if (r.has("rpy")) {
    // URDF: fixed axes X, Y, Z, i.e. R = Rz(yaw) Ry(pitch) Rx(roll).
    const auto a = r.numbers<3>("rpy");
    x.linear() = (Eigen::AngleAxisd(a[2], Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(a[1], Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(a[0], Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
  }
  return x;
}

Joint read_joint(const Json& j, std::size_t index, const std::string& source) {
  const Reader first(j, source, "joint " + std::to_string(index));
  Joint joint;
  joint.name = first.text("name");
  const Reader r(j, source, "joint \"" + joint.name + "\"");
  joint.type = read_joint_type(r);
  joint.parent = r.text("parent");
  joint.child = r.text("child");
  joint.origin = read_origin(r, source);
  if (r.has("axis")) {
    const auto a = r.numbers<3>("axis");
    joint.axis = Eigen::Vector3d(a[0], a[1], a[2]);
  }
  if (r.has("limits")) {
    const Reader l(r.at("limits"), source, r.where() + " limits");
    joint.limits = JointLimits{l.number("lower", 0.0), l.number("upper", 0.0),
                               l.number("velocity", 0.0), l.number("effort", 0.0)};
  }
  if (r.has("mimic")) {
    const Reader m(r.at("mimic"), source, r.where() + " mimic");
    joint.mimic = JointMimic{m.text("joint"), m.number("multiplier", 1.0), m.number("offset", 0.0)};
  }
  return joint;
}

std::vector<std::string> read_names(const Reader& r, const char* key) {
  std::vector<std::string> out;
  if (!r.has(key)) return out;
  const Json& v = r.at(key);
  if (!v.is_array()) r.fail(std::string("\"") + key + "\" is not a list of names");
  for (const Json& e : v) {
    if (!e.is_string())
      r.fail(std::string("\"") + key + "\" holds a value that is not a name: " + e.dump());
    out.push_back(e.get<std::string>());
  }
  return out;
}

std::map<std::string, double> read_number_map(const Reader& r, const char* key) {
  std::map<std::string, double> out;
  if (!r.has(key)) return out;
  const Json& v = r.at(key);
  if (!v.is_object()) r.fail(std::string("\"") + key + "\" is not an object of numbers");
  for (const auto& [name, x] : v.items()) {
    if (!x.is_number() || !std::isfinite(x.get<double>()))
      r.fail(std::string("\"") + key + "\" of \"" + name +
             "\" is not a finite number: " + x.dump());
    out[name] = x.get<double>();
  }
  return out;
}

// One pair: [link1, link2, class, ignored] or [link1, link2, "given", ignored, reason].
LinkPairClass read_pair(const Reader& r, const Json& p) {
  const auto bad = [&] {
    r.fail("a pair is not [link1, link2, class, ignored(, reason)]: " + p.dump());
  };
  if (!p.is_array() || p.size() < 4 || p.size() > 5 || !p[0].is_string() || !p[1].is_string() ||
      !p[2].is_string() || !p[3].is_boolean() || (p.size() == 5 && !p[4].is_string()))
    bad();
  const std::optional<PairClass> kind = parse_pair_class(p[2].get<std::string>());
  if (!kind) r.fail("a pair's class \"" + p[2].get<std::string>() + "\" is unknown: " + p.dump());
  return {p[0].get<std::string>(), p[1].get<std::string>(), *kind, p[3].get<bool>(),
          p.size() == 5 ? p[4].get<std::string>() : std::string()};
}

SelfCollisionMatrix read_matrix(const Json& j, const std::string& source) {
  const Reader r(j, source, "planner self_collision");
  SelfCollisionMatrix m;
  const double samples = r.number("samples", 0.0);
  if (samples < 0 || samples != std::floor(samples)) r.fail("\"samples\" is not a count");
  m.samples = static_cast<std::size_t>(samples);
  const double seed = r.number("seed", 0.0);
  if (seed < 0 || seed > 4294967295.0 || seed != std::floor(seed)) r.fail("\"seed\" is not a seed");
  m.seed = static_cast<unsigned>(seed);
  m.threshold = r.number("threshold", 0.0);
  m.margin = r.number("margin", 0.0);
  m.srdf = r.text("srdf", false);
  m.buffer = read_number_map(r, "buffer");
  if (r.has("pairs")) {
    if (!r.at("pairs").is_array()) r.fail("\"pairs\" is not a list");
    for (const Json& p : r.at("pairs")) m.pairs.push_back(read_pair(r, p));
  }
  return m;
}

PlannerSetup read_planner(const Json& j, const std::string& source) {
  const Reader r(j, source, "planner");
  PlannerSetup s;
  s.tool_frames = read_names(r, "tool_frames");
  s.tool_frames_from = r.text("tool_frames_from", false);
  s.locked_joints = read_names(r, "locked_joints");
  s.default_positions = read_number_map(r, "default_positions");
  s.default_from = r.text("default_from", false);
  if (r.has("self_collision")) s.self_collision = read_matrix(r.at("self_collision"), source);
  return s;
}

Json planner_json(const PlannerSetup& s) {
  Json o = Json::object();
  o["tool_frames"] = s.tool_frames;
  o["tool_frames_from"] = s.tool_frames_from;
  o["locked_joints"] = s.locked_joints;
  o["default_positions"] = Json::object();
  for (const auto& [joint, q] : s.default_positions) o["default_positions"][joint] = q;
  o["default_from"] = s.default_from;
  if (s.self_collision) {
    const SelfCollisionMatrix& m = *s.self_collision;
    Json c = {{"samples", m.samples},  {"seed", m.seed}, {"threshold", m.threshold},
              {"margin", m.margin},    {"srdf", m.srdf}, {"buffer", Json::object()},
              {"pairs", Json::array()}};
    for (const auto& [link, b] : m.buffer) c["buffer"][link] = b;
    for (const LinkPairClass& p : m.pairs) {
      Json e = {p.link1, p.link2, pair_class_name(p.kind), p.ignored};
      if (p.kind == PairClass::kGiven) e.push_back(p.reason);
      c["pairs"].push_back(std::move(e));
    }
    o["self_collision"] = std::move(c);
  }
  return o;
}

void check_header(const Json& doc, const std::string& source) {
  if (!doc.is_object()) throw InputError(source, "the top level is not a JSON object");
  const auto format = doc.find("format");
  if (format == doc.end() || !format->is_string() || format->get<std::string>() != kRobotFormat)
    throw InputError(source, std::string("\"format\" is ") +
                                 (format == doc.end() ? "missing" : format->dump()) +
                                 ", expected \"" + kRobotFormat + "\"");
  const auto version = doc.find("version");
  if (version == doc.end() || !version->is_number_integer() || version->get<long long>() < 1 ||
      version->get<long long>() > kRobotVersion)
    throw InputError(source, "robot file version " +
                                 (version == doc.end() ? std::string("missing") : version->dump()) +
                                 " is not supported (this build reads version 1 to " +
                                 std::to_string(kRobotVersion) + ")");
}

const Json& list_at(const Json& doc, const char* key, const std::string& source) {
  const auto it = doc.find(key);
  if (it == doc.end()) throw InputError(source, std::string("missing the key \"") + key + "\"");
  if (!it->is_array()) throw InputError(source, std::string("\"") + key + "\" is not a list");
  return *it;
}

Json object_from_text(const std::string& text, const std::string& what) {
  Json v;
  try {
    v = Json::parse(text.empty() ? std::string("{}") : text);
  } catch (const Json::exception& e) {
    throw std::invalid_argument(what + " is not valid JSON: " + e.what());
  }
  if (!v.is_object()) throw std::invalid_argument(what + " is not a JSON object");
  return v;
}

Json spheres_json(const SphereSet& set) {
  Json list = Json::array();
  for (const Sphere& s : set.spheres)
    list.push_back(Json::array({s.center.x(), s.center.y(), s.center.z(), s.radius}));
  return list;
}

Json joint_json(const Joint& j) {
  Json o = Json::object();
  o["name"] = j.name;
  o["type"] = joint_type_name(j.type);
  o["parent"] = j.parent;
  o["child"] = j.child;
  const Eigen::Vector3d t = j.origin.translation();
  const Eigen::Quaterniond q(j.origin.rotation());
  o["origin"] = {{"xyz", {t.x(), t.y(), t.z()}}, {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
  o["axis"] = {j.axis.x(), j.axis.y(), j.axis.z()};
  if (j.limits)
    o["limits"] = {{"lower", j.limits->lower},
                   {"upper", j.limits->upper},
                   {"velocity", j.limits->velocity},
                   {"effort", j.limits->effort}};
  if (j.mimic)
    o["mimic"] = {{"joint", j.mimic->joint},
                  {"multiplier", j.mimic->multiplier},
                  {"offset", j.mimic->offset}};
  return o;
}

// Indented JSON with every list of numbers, names or flags on one line (a sphere, a vector,
// a pair of links).
void dump_readable(const Json& v, int indent, std::string& out) {
  const bool flat_list = v.is_array() && std::all_of(v.begin(), v.end(), [](const Json& e) {
                           return e.is_number() || e.is_string() || e.is_boolean();
                         });
  if ((!v.is_object() && !v.is_array()) || flat_list || v.empty()) {
    out += v.dump();
    return;
  }
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  out += v.is_object() ? "{" : "[";
  bool first = true;
  for (auto it = v.begin(); it != v.end(); ++it) {
    out += first ? "\n" : ",\n";
    first = false;
    out += pad;
    if (v.is_object()) out += Json(it.key()).dump() + ": ";
    dump_readable(*it, indent + 2, out);
  }
  out += "\n" + std::string(static_cast<std::size_t>(indent), ' ') + (v.is_object() ? "}" : "]");
}

}  // namespace

RobotModel parse_robot(const std::string& json_text, const std::string& source) {
  Json doc;
  try {
    doc = Json::parse(json_text);
  } catch (const Json::exception& e) {
    throw InputError(source, std::string("not valid JSON: ") + e.what());
  }
  check_header(doc, source);
  const Reader top(doc, source, "robot");
  RobotModel model;
  model.name = top.text("name", false);
  model.root_link = top.text("root_link", false);
  const Json& links = list_at(doc, "links", source);
  for (std::size_t i = 0; i < links.size(); ++i)
    model.links.push_back(read_link(links[i], i, source));
  const Json& joints = list_at(doc, "joints", source);
  for (std::size_t i = 0; i < joints.size(); ++i)
    model.joints.push_back(read_joint(joints[i], i, source));
  if (top.has("metadata")) {
    if (!doc.at("metadata").is_object()) top.fail("\"metadata\" is not a JSON object");
    model.metadata_json = doc.at("metadata").dump();
  }
  if (top.has("planner")) model.planner = read_planner(doc.at("planner"), source);
  validate_robot_model(model, source);
  return model;
}

RobotModel load_robot(const std::string& path) {
  return parse_robot(read_text_file(path), path);
}

std::string robot_to_json(const RobotModel& model) {
  Json doc = Json::object();
  doc["format"] = kRobotFormat;
  doc["version"] = kRobotVersion;
  doc["name"] = model.name;
  doc["root_link"] = model.root_link;
  Json links = Json::array();
  for (const Link& l : model.links) {
    Json o = {{"name", l.name},
              {"inner", spheres_json(l.spheres.inner)},
              {"outer", spheres_json(l.spheres.outer)}};
    if (!l.spheres.outer_certificate_json.empty())
      o["outer_certificate"] = object_from_text(l.spheres.outer_certificate_json,
                                                "link \"" + l.name + "\" outer certificate");
    if (l.spheres.inner_filled) o["inner_solid"] = "filled";
    if (!l.note.empty()) o["note"] = l.note;
    links.push_back(std::move(o));
  }
  doc["links"] = std::move(links);
  Json joints = Json::array();
  for (const Joint& j : model.joints) joints.push_back(joint_json(j));
  doc["joints"] = std::move(joints);
  if (model.planner) doc["planner"] = planner_json(*model.planner);
  doc["metadata"] = object_from_text(model.metadata_json, "RobotModel::metadata_json");
  std::string out;
  dump_readable(doc, 0, out);
  return out + "\n";
}

namespace {

Json robot_document(const std::string& robot_json, const std::string& source) {
  Json doc = Json::parse(robot_json, nullptr, false);
  if (doc.is_discarded() || !doc.is_object())
    throw InputError(source, "is not a JSON object (a robot file)");
  return doc;
}

}  // namespace

std::string robot_json_with_metadata(const std::string& robot_json,
                                     const std::string& metadata_json, const std::string& source) {
  Json doc = robot_document(robot_json, source);
  doc["metadata"] = object_from_text(metadata_json, "metadata");
  std::string out;
  dump_readable(doc, 0, out);
  return out + "\n";
}

std::string robot_json_metadata(const std::string& robot_json, const std::string& source) {
  const Json doc = robot_document(robot_json, source);
  const auto it = doc.find("metadata");
  return it == doc.end() ? std::string("{}") : it->dump();
}

void save_robot(const RobotModel& model, const std::string& path) {
  validate_robot_model(model, path);
  write_file_atomically(path, robot_to_json(model));
}

}  // namespace medspheres
