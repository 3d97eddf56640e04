#include "medspheres/formats/sphere_document.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "medspheres/error.h"
#include "medspheres/formats/curobo_urdf_check.h"
#include "medspheres/formats/curobo_yaml.h"
#include "medspheres/formats/foam_json.h"
#include "medspheres/formats/planner_options.h"
#include "medspheres/formats/sph_file.h"
#include "medspheres/formats/spherized_urdf.h"
#include "medspheres/formats/srdf_spheres.h"
#include "medspheres/formats/xrdf.h"
#include "medspheres/io.h"
#include "medspheres/robot_file.h"
#include "xml_text.h"

namespace medspheres::formats {

namespace {

constexpr SphereFormat kAll[] = {
    SphereFormat::kSphereSet, SphereFormat::kRobot, SphereFormat::kCurobo, SphereFormat::kXrdf,
    SphereFormat::kUrdf,      SphereFormat::kSrdf,  SphereFormat::kFoam,   SphereFormat::kSph};

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A ".json" file by its content.
SphereFormat json_format(const std::string& text) {
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (doc.is_object()) {
    const auto f = doc.find("format");
    if (f != doc.end() && f->is_string() && f->get<std::string>() == kRobotFormat)
      return SphereFormat::kRobot;
    if (doc.contains("spheres") || f != doc.end()) return SphereFormat::kSphereSet;
    return SphereFormat::kFoam;
  }
  return doc.is_array() ? SphereFormat::kFoam : SphereFormat::kSphereSet;
}

// Level \p level of \p levels (-1: the last).
template <class Levels>
std::size_t pick_level(const Levels& levels, int level, const std::string& source) {
  if (level < 0) return levels.size() - 1;
  if (static_cast<std::size_t>(level) >= levels.size())
    throw InputError(source, "has " + std::to_string(levels.size()) + " levels; level " +
                                 std::to_string(level) + " does not exist (--level counts from 0)");
  return static_cast<std::size_t>(level);
}

SphereSet one_set(std::vector<Sphere> spheres) {
  SphereSet set;
  set.spheres = std::move(spheres);
  return set;
}

std::string xml_robot_name(const std::string& text, const std::string& source) {
  tinyxml2::XMLDocument xml;
  parse_xml(xml, text, source);
  const char* name = xml_root(xml, "robot", source).Attribute("name");
  return name ? name : "";
}

}  // namespace

SphereDocument robot_document(const RobotModel& model, SphereChoice choice,
                              const std::string& urdf_text, const std::string& source) {
  SphereDocument doc;
  doc.model = model;
  doc.robot_name = model.name;
  doc.urdf_text = urdf_text;
  doc.links = robot_spheres(model, choice);
  if (doc.links.empty())
    throw InputError(
        source, std::string("no link has ") +
                    (choice == SphereChoice::kOuter ? "outer (covering)" : "inner") + " spheres" +
                    (choice == SphereChoice::kOuter ? " (pick the inner set instead)" : ""));
  return doc;
}

const char* sphere_format_name(SphereFormat format) {
  switch (format) {
    case SphereFormat::kSphereSet:
      return "spheres";
    case SphereFormat::kRobot:
      return "robot";
    case SphereFormat::kCurobo:
      return "curobo";
    case SphereFormat::kXrdf:
      return "xrdf";
    case SphereFormat::kUrdf:
      return "urdf";
    case SphereFormat::kSrdf:
      return "srdf";
    case SphereFormat::kFoam:
      return "foam";
    case SphereFormat::kSph:
      return "sph";
  }
  return "unknown";
}

SphereFormat parse_sphere_format(const std::string& name, const std::string& option) {
  std::string known;
  for (SphereFormat f : kAll) {
    if (name == sphere_format_name(f)) return f;
    known += std::string(known.empty() ? "" : ", ") + sphere_format_name(f);
  }
  throw InputError(option, "unknown format \"" + name + "\" (known: " + known + ")");
}

SphereFormat sphere_format_of_path(const std::string& path) {
  if (ends_with(path, ".robot.json")) return SphereFormat::kRobot;
  if (ends_with(path, ".foam.json")) return SphereFormat::kFoam;
  if (ends_with(path, ".json")) return SphereFormat::kSphereSet;
  if (ends_with(path, ".yml") || ends_with(path, ".yaml")) return SphereFormat::kCurobo;
  if (ends_with(path, ".xrdf")) return SphereFormat::kXrdf;
  if (ends_with(path, ".urdf")) return SphereFormat::kUrdf;
  if (ends_with(path, ".srdf")) return SphereFormat::kSrdf;
  if (ends_with(path, ".sph")) return SphereFormat::kSph;
  throw InputError(path,
                   "cannot tell the sphere format from the extension (.json, .robot.json, "
                   ".foam.json, .yml, .xrdf, .urdf, .srdf, .sph); name it with --from/--to");
}

SphereDocument read_sphere_document(const std::string& path, std::optional<SphereFormat> format,
                                    const ReadOptions& options) {
  if (options.level < -1)
    throw InputError::option(ErrorKind::kOutOfRange, "level", std::to_string(options.level),
                             "must be a level counted from 0 at the root, or -1 for the last");
  const std::string text = read_text_file(path);
  SphereFormat f = format ? *format : sphere_format_of_path(path);
  if (!format && f == SphereFormat::kSphereSet && !ends_with(path, ".spheres.json"))
    f = json_format(text);
  SphereDocument doc;
  switch (f) {
    case SphereFormat::kSphereSet:
      doc.set = parse_sphere_set(text, path);
      break;
    case SphereFormat::kRobot:
      return robot_document(parse_robot(text, path), options.choice, "", path);
    case SphereFormat::kCurobo:
      doc.links = parse_curobo_yaml(text, path);
      break;
    case SphereFormat::kXrdf:
      doc.links = parse_xrdf(text, path);
      break;
    case SphereFormat::kUrdf:
      doc.links = parse_urdf_spheres(text, path);
      doc.urdf_text = text;
      doc.robot_name = xml_robot_name(text, path);
      break;
    case SphereFormat::kSrdf:
      doc.links = parse_srdf_spheres(text, path);
      doc.robot_name = xml_robot_name(text, path);
      break;
    case SphereFormat::kFoam:
      if (is_foam_robot_json(text)) {
        doc.links = parse_foam_robot_json(text, path);
      } else {
        const auto levels = parse_foam_mesh_json(text, path);
        doc.set = one_set(levels[pick_level(levels, options.level, path)].spheres);
      }
      break;
    case SphereFormat::kSph: {
      const auto levels = parse_sph_levels(text, path);
      doc.set = one_set(levels[pick_level(levels, options.level, path)]);
      break;
    }
  }
  return doc;
}

std::map<std::string, std::vector<Sphere>> read_link_sphere_map(const std::string& path,
                                                                const std::string& option) {
  const SphereDocument doc = read_sphere_document(path);
  if (doc.set)
    throw InputError::option(ErrorKind::kOutOfRange, option, path,
                             "holds one sphere set; a robot needs a per-link file (cuRobo, "
                             "XRDF, spherized URDF, SRDF, foam database, robot file)");
  std::map<std::string, std::vector<Sphere>> out;
  for (const LinkSphereList& l : doc.links) out[l.link] = l.spheres;
  return out;
}

std::vector<Sphere> one_set_of(const SphereDocument& doc, const std::string& link,
                               const std::string& link_field) {
  if (doc.set) return doc.set->spheres;
  if (link.empty()) {
    if (doc.links.size() == 1) return doc.links.front().spheres;
    std::string names;
    for (const LinkSphereList& l : doc.links) names += (names.empty() ? "" : ", ") + l.link;
    throw InputError::option(ErrorKind::kOutOfRange, link_field, "",
                             "the input has spheres for " + std::to_string(doc.links.size()) +
                                 " links; pick one (" + names + ")");
  }
  if (const LinkSphereList* l = find_link_spheres(doc.links, link)) return l->spheres;
  throw InputError::option(ErrorKind::kOutOfRange, link_field, "",
                           "the input has no spheres for the link \"" + link + "\"");
}

namespace {

// The one set a one-set format writes.
std::vector<Sphere> single_set(const SphereDocument& doc, const WriteOptions& options) {
  return one_set_of(doc, options.link);  // --link only names the link of a one-set input
}

// The per-link spheres a per-link format writes: every link of a per-link input (a link
// named for it would be left unused, so it is refused), or a one-set input as the link named.
RobotSpheres per_link(const SphereDocument& doc, const WriteOptions& options) {
  if (!doc.set && !options.link.empty())
    throw InputError::option(ErrorKind::kConflict, "link", options.link,
                             "the input has spheres per link and the output format takes every "
                             "one of them; a link is named only for a one-set input or output");
  if (!doc.set) return doc.links;
  if (options.link.empty())
    throw InputError::option(ErrorKind::kOutOfRange, "link", "",
                             "the input holds one sphere set; say which link it is for");
  return {LinkSphereList{options.link, doc.set->spheres}};
}

std::string robot_name(const SphereDocument& doc, const WriteOptions& options) {
  if (!options.robot_name.empty()) return options.robot_name;
  return doc.robot_name.empty() ? "robot" : doc.robot_name;
}

}  // namespace

std::string sphere_document_text(const SphereDocument& doc, SphereFormat format,
                                 const WriteOptions& options) {
  switch (format) {
    case SphereFormat::kSphereSet: {
      SphereSet set = one_set(single_set(doc, options));
      if (doc.set) set.metadata_json = doc.set->metadata_json;
      validate_sphere_set(set, "sphere set");
      return sphere_set_to_json(set);
    }
    case SphereFormat::kRobot:
      if (!doc.model)
        throw InputError("robot file",
                         "a medspheres robot file needs the kinematic tree, which "
                         "only a robot file (or the robot command) provides");
      return robot_to_json(*doc.model);
    case SphereFormat::kCurobo: {
      const RobotSpheres spheres = per_link(doc, options);
      CuroboOptions o;
      if (doc.model) o = curobo_options(*doc.model, spheres, options.curobo, options.urdf_path);
      o.layout = options.curobo;
      return curobo_yaml_text(spheres, o);
    }
    case SphereFormat::kXrdf: {
      if (doc.model && !writes_xrdf(*doc.model))
        throw InputError::option(
            ErrorKind::kOutOfRange, "to", "xrdf",
            "the robot has no actuated joint, and cuRobo's XRDF loaders need one in the cspace "
            "(v1 and v2 take the largest of its acceleration limits); the cuRobo YAML "
            "(--to curobo) carries the spheres");
      const RobotSpheres spheres = per_link(doc, options);
      return xrdf_text(spheres, doc.model ? xrdf_options(*doc.model, spheres) : XrdfOptions{});
    }
    case SphereFormat::kUrdf: {
      const bool given = !options.urdf_text.empty();
      if (!given && doc.urdf_text.empty())
        throw InputError::option(ErrorKind::kOutOfRange, "urdf", "",
                                 "a spherized URDF is made from the robot's URDF; pass it");
      return spherize_urdf(given ? options.urdf_text : doc.urdf_text, per_link(doc, options),
                           given ? options.urdf_source : "the input URDF");
    }
    case SphereFormat::kSrdf: {
      const RobotSpheres spheres = per_link(doc, options);
      return srdf_spheres_text(
          spheres, robot_name(doc, options),
          doc.model ? srdf_disabled_pairs(*doc.model, spheres) : std::vector<DisabledCollision>{});
    }
    case SphereFormat::kFoam:
      if (doc.set || !options.link.empty()) return foam_mesh_json(single_set(doc, options));
      return foam_robot_json(doc.links);
    case SphereFormat::kSph:
      return sph_text(single_set(doc, options));
  }
  throw std::invalid_argument("sphere_document_text: unknown format");
}

void write_sphere_document(const std::string& path, const SphereDocument& doc, SphereFormat format,
                           const WriteOptions& options) {
  std::string text;
  try {
    text = sphere_document_text(doc, format, options);
  } catch (const InputError& e) {
    // A writer without a path names its format (".sph: no spheres to write"); here is one.
    if (e.field().empty() && e.file() == "." + std::string(sphere_format_name(format)))
      throw e.with_file(path);
    throw;
  }
  write_file_atomically(path, text);
}

}  // namespace medspheres::formats
