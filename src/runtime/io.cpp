#include "medspheres/io.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include "medspheres/error.h"

namespace medspheres {

using Json = nlohmann::ordered_json;

namespace {

std::string read_whole_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, std::string("cannot open for reading: ") + std::strerror(errno));
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw InputError(path, "read error");
  return buf.str();
}

double read_number(const Json& v, const std::string& source, std::size_t sphere, int field) {
  static const char* names[] = {"x", "y", "z", "radius"};
  if (!v.is_number()) {
    throw InputError(source, "sphere " + std::to_string(sphere) + ": " + names[field] +
                                 " is not a number (" + v.dump() + ")");
  }
  return v.get<double>();
}

}  // namespace

SphereSet parse_sphere_set(const std::string& json_text, const std::string& source) {
  Json doc;
  try {
    doc = Json::parse(json_text);
  } catch (const Json::exception& e) {  // parse errors and number overflow alike
    throw InputError(source, std::string("not valid JSON: ") + e.what());
  }
  if (!doc.is_object()) throw InputError(source, "the top level is not a JSON object");

  if (auto it = doc.find("format"); it != doc.end()) {
    if (!it->is_string() || it->get<std::string>() != kSphereSetFormat)
      throw InputError(source,
                       "\"format\" is " + it->dump() + ", expected \"" + kSphereSetFormat + "\"");
  }
  if (auto it = doc.find("version"); it != doc.end()) {
    if (!it->is_number_integer())
      throw InputError(source, "\"version\" is " + it->dump() + ", expected an integer");
    const auto v = it->get<long long>();
    if (v < 1 || v > kSphereSetVersion)
      throw InputError(source, "sphere-set file version " + std::to_string(v) +
                                   " is not supported (this build reads version 1 to " +
                                   std::to_string(kSphereSetVersion) + ")");
  }

  auto it = doc.find("spheres");
  if (it == doc.end()) throw InputError(source, "missing the required key \"spheres\"");
  if (!it->is_array()) throw InputError(source, "\"spheres\" is not an array");

  SphereSet set;
  set.spheres.reserve(it->size());
  for (std::size_t i = 0; i < it->size(); ++i) {
    const Json& e = (*it)[i];
    if (!e.is_array() || e.size() != 4)
      throw InputError(source, "sphere " + std::to_string(i) +
                                   " is not an array of four numbers [x, y, z, r]: " + e.dump());
    Sphere s;
    for (int k = 0; k < 3; ++k) s.center[k] = read_number(e[k], source, i, k);
    s.radius = read_number(e[3], source, i, 3);
    set.spheres.push_back(s);
  }
  validate_sphere_set(set, source);

  Json meta = Json::object();
  for (auto m = doc.begin(); m != doc.end(); ++m) {
    if (m.key() == "format" || m.key() == "version" || m.key() == "spheres") continue;
    meta[m.key()] = m.value();
  }
  set.metadata_json = meta.dump();
  return set;
}

SphereSet load_sphere_set(const std::string& path) {
  return parse_sphere_set(read_whole_file(path), path);
}

std::string sphere_set_to_json(const SphereSet& set) {
  Json meta;
  try {
    meta = Json::parse(set.metadata_json.empty() ? std::string("{}") : set.metadata_json);
  } catch (const Json::parse_error& e) {
    throw std::invalid_argument(std::string("SphereSet::metadata_json is not valid JSON: ") +
                                e.what());
  }
  if (!meta.is_object())
    throw std::invalid_argument("SphereSet::metadata_json is not a JSON object");

  std::string out = "{\n  \"format\": \"";
  out += kSphereSetFormat;
  out += "\",\n  \"version\": " + std::to_string(kSphereSetVersion) + ",\n  \"spheres\": [";
  for (std::size_t i = 0; i < set.spheres.size(); ++i) {
    const Sphere& s = set.spheres[i];
    // A JSON array of doubles dumps in the shortest form that reads back bit-identical.
    Json row = Json::array({s.center.x(), s.center.y(), s.center.z(), s.radius});
    out += (i == 0 ? "\n    " : ",\n    ") + row.dump();
  }
  out += set.spheres.empty() ? "]" : "\n  ]";
  for (auto m = meta.begin(); m != meta.end(); ++m) {
    if (m.key() == "format" || m.key() == "version" || m.key() == "spheres") continue;
    std::string value = m.value().dump(2);
    // Indent nested lines by two more spaces so the object sits under its key.
    std::string indented;
    for (char c : value) {
      indented += c;
      if (c == '\n') indented += "  ";
    }
    out += ",\n  " + Json(m.key()).dump() + ": " + indented;
  }
  out += "\n}\n";
  return out;
}

void save_sphere_set(const SphereSet& set, const std::string& path) {
  validate_sphere_set(set, path);
  write_file_atomically(path, sphere_set_to_json(set));
}

void write_file_atomically(const std::string& path, const std::string& contents) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error(path + ": cannot write: directory " + dir.string() + " does not exist");

  static std::atomic_uint counter{0};  // two writers in one process never share a name
  const fs::path tmp = dir / ("." + target.filename().string() + ".tmp." +
                              std::to_string(::getpid()) + "." + std::to_string(counter++));
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw Error(path + ": cannot write: " + std::strerror(errno));
  bool ok = std::fwrite(contents.data(), 1, contents.size(), f) == contents.size();
  ok = (std::fflush(f) == 0) && ok;
  ok = (::fsync(::fileno(f)) == 0) && ok;
  const int saved_errno = errno;
  ok = (std::fclose(f) == 0) && ok;
  if (!ok) {
    fs::remove(tmp, ec);
    throw Error(path + ": cannot write: " + std::strerror(saved_errno));
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(path + ": cannot write: " + ec.message());
  }
}

}  // namespace medspheres
