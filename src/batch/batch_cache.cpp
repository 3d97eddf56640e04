// The batch cache: baked files keyed by the mesh's bytes, the request and the version.
#include "medspheres/batch/batch_cache.h"

#include <cctype>
#include <filesystem>
#include <system_error>

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/number_text.h"
#include "medspheres/sha256.h"
#include "medspheres/version.h"

namespace medspheres {

namespace fs = std::filesystem;

namespace {

std::string optional_text(const std::optional<double>& v) {
  return v ? exact_number_text(*v) : "none";
}

std::string optional_text(const std::optional<Length>& l) {
  return l ? exact_number_text(l->value) + (l->relative ? "L" : "") : "none";
}

}  // namespace

std::string spheres_text(const std::vector<Sphere>& spheres) {
  std::string t;
  for (const Sphere& b : spheres)
    t += exact_number_text(b.center.x()) + " " + exact_number_text(b.center.y()) + " " +
         exact_number_text(b.center.z()) + " " + exact_number_text(b.radius) + ";";
  return t;
}

// A new field of BakeRequest or BakeOptions that changes the result must be added here.
std::string bake_request_text(const BakeRequest& r) {
  std::string t;
  auto line = [&t](const char* name, const std::string& value) {
    t += name;
    t += '=';
    t += value;
    t += '\n';
  };
  line("method", r.method == BakeMethod::kCover ? "cover" : "medial");
  line("resolution", std::to_string(r.medial.resolution));
  line("object_angle", exact_number_text(r.medial.object_angle));
  line("medial_tolerance", exact_number_text(r.medial.medial_tolerance));
  line("max_spheres", r.max_spheres ? std::to_string(*r.max_spheres) : "none");
  if (!r.cover_start.empty()) line("cover_start", spheres_text(r.cover_start));
  line("target_error", optional_text(r.target_error));
  line("dilate", r.dilate ? "1" : "0");
  line("vertex_tolerance", optional_text(r.vertex_tolerance));
  line("max_protrusion", optional_text(r.max_protrusion));
  line("cover", optional_text(r.cover));
  line("seed", std::to_string(r.seed));
  line("measure", r.measure ? "1" : "0");
  line("record_seconds", r.record_seconds ? "1" : "0");
  line("solid", to_string(r.solid));
  line("robust_resolution", std::to_string(r.robust.resolution));
  line("robust_thickness", r.robust_thickness ? optional_text(r.robust_thickness)
                                              : exact_number_text(r.robust.thickness));
  line("cover_search", exact_number_text(r.cover_search.protrusion_allowance) + " " +
                           std::to_string(r.cover_search.protrusion_restarts) + " " +
                           std::to_string(r.cover_search.balance_rounds));
  return t;
}

std::string bake_cache_key(const std::string& mesh_sha256, const std::string& extension,
                           const BakeRequest& request) {
  std::string ext = extension;
  if (!ext.empty() && ext.front() == '.') ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return sha256_hex(std::string("medspheres bake cache 1\nversion=") + MEDSPHERES_VERSION_STRING +
                    "\nrevision=" + std::to_string(MEDSPHERES_OUTPUT_REVISION) + "\nmesh=" +
                    mesh_sha256 + "\nextension=" + ext + "\n" + bake_request_text(request));
}

BakeCache::BakeCache(std::string dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (!fs::is_directory(dir_))
    throw InputError::option(ErrorKind::kWriteFailed, "cache", dir_,
                             "'" + dir_ + "' is not a folder and cannot be made one" +
                                 (ec ? " (" + ec.message() + ")" : std::string()));
}

std::string BakeCache::path_of(const std::string& key, const std::string& suffix) const {
  return (fs::path(dir_) / key.substr(0, 2) / (key + suffix)).string();
}

std::optional<std::string> BakeCache::find_bytes(const std::string& key,
                                                 const std::string& suffix) const {
  const std::string path = path_of(key, suffix);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  try {
    return read_text_file(path);
  } catch (const InputError&) {
    return std::nullopt;  // removed meanwhile, or unreadable: bake again, store again
  }
}

std::optional<SphereSet> BakeCache::find(const std::string& key) const {
  const std::optional<std::string> text = find_bytes(key, ".spheres.json");
  if (!text) return std::nullopt;
  try {
    return parse_sphere_set(*text, path_of(key));
  } catch (const InputError&) {
    return std::nullopt;  // torn by hand or another tool: bake again, store again
  }
}

void BakeCache::store_bytes(const std::string& key, const std::string& suffix,
                            const std::string& bytes) const {
  const fs::path path = path_of(key, suffix);
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);  // a racing worker may make it first
  write_file_atomically(path.string(), bytes);
}

void BakeCache::store(const std::string& key, const std::string& json_text) const {
  store_bytes(key, ".spheres.json", json_text);
}

}  // namespace medspheres
