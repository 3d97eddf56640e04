// The files of a robot bake's output folder (robot_outputs.h).
#include "medspheres/formats/robot_outputs.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <system_error>

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include "medspheres/error.h"
#include "medspheres/formats/curobo_urdf_check.h"
#include "medspheres/formats/self_collision_report.h"
#include "medspheres/io.h"

namespace medspheres::formats {

namespace fs = std::filesystem;

namespace {

// The file each format is written to in the folder, after the robot's name (sanitised);
// .sph holds one set, so it gets a folder with one file per link.
std::string file_stem(const std::string& robot_name) {
  std::string stem = robot_name.empty() ? "robot" : robot_name;
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '_';
  return stem;
}

std::string format_file(SphereFormat f, const std::string& stem) {
  switch (f) {
    case SphereFormat::kRobot:
      return stem + ".robot.json";
    case SphereFormat::kCurobo:
      return stem + ".curobo.yml";
    case SphereFormat::kXrdf:
      return stem + ".xrdf";
    case SphereFormat::kUrdf:
      return stem + ".spherized.urdf";
    case SphereFormat::kSrdf:
      return stem + ".srdf";
    case SphereFormat::kFoam:
      return stem + ".foam.json";
    case SphereFormat::kSph:
      return "sph";
    case SphereFormat::kSphereSet:
      break;
  }
  return {};
}

// One .sph file per link with spheres, named after the link (sanitised; a clash gets the
// link's index), under \p dir in \p files.
void add_sph_files(const SphereDocument& doc, const std::string& dir,
                   std::map<std::string, std::string>& files) {
  std::set<std::string> used;
  for (std::size_t i = 0; i < doc.links.size(); ++i) {
    std::string name = file_stem(doc.links[i].link);
    if (!used.insert(name).second) name += "_" + std::to_string(i);
    used.insert(name);
    WriteOptions options;
    options.link = doc.links[i].link;
    files[dir + "/" + name + ".sph"] = sphere_document_text(doc, SphereFormat::kSph, options);
  }
}

// A fresh folder beside \p out, removed by the destructor unless it was moved into place.
class StagingDir {
 public:
  explicit StagingDir(const std::string& out) {
    const fs::path target = fs::absolute(out).lexically_normal();
    std::random_device random;
    for (int attempt = 0; attempt < 100 && path_.empty(); ++attempt) {
      const fs::path p =
          target.parent_path() / ("." + target.filename().string() + ".tmp-" +
                                  std::to_string(::getpid()) + "-" + std::to_string(random()));
      if (fs::create_directory(p)) path_ = p;
    }
    if (path_.empty()) throw Error(out + ": cannot create a temporary folder beside it");
    target_ = target;
  }
  ~StagingDir() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  StagingDir(const StagingDir&) = delete;
  StagingDir& operator=(const StagingDir&) = delete;

  std::string path() const { return path_.string(); }

  // Moves the folder to the target: a rename when nothing is there, an atomic exchange
  // with an existing folder (whose old contents are then removed).
  void commit() {
    if (!fs::exists(target_)) {
      fs::rename(path_, target_);
      path_.clear();
      return;
    }
    if (::renameat2(AT_FDCWD, path_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0)
      throw Error(target_.string() + ": cannot replace the folder: " +
                  std::error_code(errno, std::generic_category()).message());
    // path_ now holds the old contents, which the destructor removes.
  }

 private:
  fs::path path_;
  fs::path target_;
};

}  // namespace

const std::vector<SphereFormat>& robot_formats() {
  static const std::vector<SphereFormat> all = {
      SphereFormat::kRobot, SphereFormat::kCurobo, SphereFormat::kXrdf, SphereFormat::kUrdf,
      SphereFormat::kSrdf,  SphereFormat::kFoam,   SphereFormat::kSph};
  return all;
}

std::vector<SphereFormat> robot_output_formats(const std::vector<std::string>& names) {
  if (names.empty()) return robot_formats();
  std::vector<SphereFormat> out;
  for (const std::string& n : names) {
    SphereFormat f;
    try {
      f = parse_sphere_format(n, "format");
    } catch (const InputError& e) {
      throw InputError::option(ErrorKind::kOutOfRange, "format", n, e.problem());
    }
    if (std::find(robot_formats().begin(), robot_formats().end(), f) == robot_formats().end())
      throw InputError::option(ErrorKind::kOutOfRange, "format", n,
                               "'" + n +
                                   "' holds one sphere set, not a robot (robot formats: robot, "
                                   "curobo, xrdf, urdf, srdf, foam, sph)");
    if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
  }
  return out;
}

std::optional<SphereChoice> parse_set_choice(const std::string& set) {
  if (set == "inner") return SphereChoice::kInner;
  if (set == "outer") return SphereChoice::kOuter;
  if (set == "auto") return std::nullopt;
  throw InputError::option(ErrorKind::kOutOfRange, "set", set,
                           "must be auto, inner or outer, got '" + set + "'");
}

SphereChoice robot_output_choice(std::optional<SphereChoice> chosen, const RobotModel& model) {
  if (chosen) return *chosen;
  const bool any_outer = std::any_of(model.links.begin(), model.links.end(),
                                     [](const Link& l) { return !l.spheres.outer.empty(); });
  return any_outer ? SphereChoice::kOuter : SphereChoice::kInner;
}

// OUT must be a folder or nothing, in a folder that exists.
void check_output_dir(const std::string& out) {
  std::error_code ec;
  const fs::file_status st = fs::status(out, ec);
  if (fs::exists(st) && !fs::is_directory(st))
    throw InputError(out, "exists and is not a folder (-o names the output folder)");
  const fs::path parent = fs::absolute(out).parent_path();
  if (!fs::is_directory(parent, ec))
    throw InputError(out, "the folder " + parent.string() + " does not exist");
}

std::map<std::string, std::string> robot_output_files(const std::vector<SphereFormat>& chosen,
                                                      const RobotModel& model, SphereChoice choice,
                                                      const std::string& urdf) {
  SphereDocument doc;
  doc.model = model;
  doc.links = robot_spheres(model, choice);
  doc.urdf_text = read_text_file(urdf);
  doc.robot_name = model.name;
  WriteOptions options;
  options.urdf_text = doc.urdf_text;
  options.urdf_source = urdf;
  options.urdf_path = fs::absolute(urdf).lexically_normal().string();
  const std::string stem = file_stem(model.name);
  std::map<std::string, std::string> files;
  for (const SphereFormat f : chosen) {
    if (f == SphereFormat::kSph) {
      add_sph_files(doc, format_file(f, stem), files);
    } else if (f == SphereFormat::kCurobo) {
      // v2's configuration, v1's, and the spheres alone for a configuration of one's own.
      for (const auto& [layout, suffix] :
           {std::pair{CuroboLayout::kV2, ".curobo.yml"},
            std::pair{CuroboLayout::kV1, ".curobo_v1.yml"},
            std::pair{CuroboLayout::kSpheres, ".curobo_spheres.yml"}}) {
        options.curobo = layout;
        files[stem + suffix] = sphere_document_text(doc, f, options);
      }
    } else if (f != SphereFormat::kXrdf || writes_xrdf(model)) {
      files[format_file(f, stem)] = sphere_document_text(doc, f, options);
    }
  }
  const bool robot_file =
      std::find(chosen.begin(), chosen.end(), SphereFormat::kRobot) != chosen.end();
  if (robot_file && model.planner && model.planner->self_collision)
    files[stem + ".self_collision.txt"] = self_collision_report(model, doc.links);
  return files;
}

void write_output_folder(const std::string& out, const std::map<std::string, std::string>& files) {
  StagingDir staging(out);
  for (const auto& [name, text] : files) {
    const fs::path path = fs::path(staging.path()) / name;
    fs::create_directories(path.parent_path());
    write_file_atomically(path.string(), text);
  }
  staging.commit();
}

void write_robot_outputs(const std::string& out, const std::vector<SphereFormat>& chosen,
                         const RobotModel& model, SphereChoice choice, const std::string& urdf) {
  write_output_folder(out, robot_output_files(chosen, model, choice, urdf));
}

}  // namespace medspheres::formats
