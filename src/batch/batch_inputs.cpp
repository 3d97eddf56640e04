// The inputs of a batch bake: files, folders scanned by extension, list files.
#include "medspheres/batch/batch_inputs.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <system_error>

#include "medspheres/error.h"

namespace medspheres {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::vector<std::string> kept_extensions(const InputScan& scan) {
  if (scan.extensions.empty()) return default_mesh_extensions();
  std::vector<std::string> out;
  for (std::string e : scan.extensions) {
    if (!e.empty() && e.front() == '.') e.erase(0, 1);
    if (e.empty() || e.find_first_of("./\\") != std::string::npos)
      throw InputError::option(ErrorKind::kOutOfRange, "extensions", e,
                               "'" + e + "' is not a file extension (write stl or .stl)");
    out.push_back(lower(e));
  }
  return out;
}

bool has_extension(const fs::path& p, const std::vector<std::string>& kept) {
  std::string e = lower(p.extension().string());
  if (e.empty()) return false;
  return std::find(kept.begin(), kept.end(), e.substr(1)) != kept.end();
}

// Every kept file below \p dir, relative to it. Unreadable subfolders are skipped; a
// folder that cannot be opened at all is an error of its own.
void scan_folder(const fs::path& dir, const std::vector<std::string>& kept,
                 std::vector<BatchInput>& out) {
  std::error_code ec;
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec);
  if (ec) throw InputError(ErrorKind::kFileUnreadable, dir.string(), "cannot list the folder");
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) throw InputError(ErrorKind::kFileUnreadable, dir.string(), ec.message());
    const fs::path& p = it->path();
    if (!it->is_regular_file(ec) || !has_extension(p, kept)) continue;
    out.push_back({p.string(), p.lexically_relative(dir).generic_string()});
  }
}

// A file given by path: relative to \p base, or its name when outside.
BatchInput file_input(const std::string& path, const fs::path& base) {
  const fs::path rel = fs::absolute(path).lexically_normal().lexically_relative(base);
  const std::string text = rel.generic_string();
  const bool outside = text.empty() || text == "." || *rel.begin() == "..";
  return {path, outside ? fs::path(path).filename().generic_string() : text};
}

// The same file twice is kept once; two files with one output are an error.
void drop_duplicates(std::vector<BatchInput>& inputs) {
  std::sort(inputs.begin(), inputs.end(), [](const BatchInput& a, const BatchInput& b) {
    return a.relative != b.relative ? a.relative < b.relative : a.path < b.path;
  });
  std::map<std::string, const BatchInput*> by_output;
  std::vector<BatchInput> kept;
  for (const BatchInput& in : inputs) {
    const std::string out = output_relative(in.relative);
    auto [at, fresh] = by_output.emplace(out, &in);
    if (fresh) {
      kept.push_back(in);
      continue;
    }
    std::error_code ec;
    const BatchInput& first = *at->second;
    if (first.relative == in.relative && fs::equivalent(first.path, in.path, ec)) continue;
    if (first.relative == in.relative && first.path == in.path) continue;
    throw InputError(ErrorKind::kConflict, in.path,
                     "would write the same output " + out + " as " + first.path);
  }
  inputs = std::move(kept);
}

std::string trimmed(std::string line) {
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!line.empty() && blank(line.back())) line.pop_back();
  std::size_t start = 0;
  while (start < line.size() && blank(line[start])) ++start;
  return line.substr(start);
}

}  // namespace

const std::vector<std::string>& default_mesh_extensions() {
  static const std::vector<std::string> all = {"stl",  "obj", "ply", "off", "dae",
                                               "gltf", "glb", "fbx", "3ds"};
  return all;
}

std::vector<BatchInput> collect_inputs(const std::vector<std::string>& paths,
                                       const InputScan& scan) {
  const std::vector<std::string> kept = kept_extensions(scan);
  const fs::path base =
      fs::absolute(scan.relative_to.empty() ? fs::current_path() : fs::path(scan.relative_to))
          .lexically_normal();
  std::vector<BatchInput> out;
  for (const std::string& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec))
      scan_folder(p, kept, out);
    else
      out.push_back(file_input(p, base));
  }
  drop_duplicates(out);
  return out;
}

std::vector<std::string> read_path_list(std::istream& in, const std::string& source) {
  std::vector<std::string> out;
  std::string line;
  while (std::getline(in, line)) {
    line = trimmed(line);
    if (!line.empty() && line.front() != '#') out.push_back(line);
  }
  if (in.bad()) throw InputError(ErrorKind::kFileUnreadable, source, "cannot read the list");
  return out;
}

std::string output_relative(const std::string& relative) {
  fs::path p(relative);
  return (p.parent_path() / (p.stem().string() + ".spheres.json")).generic_string();
}

}  // namespace medspheres
