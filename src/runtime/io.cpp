#include "medspheres/io.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "medspheres/error.h"

namespace medspheres {

using Json = nlohmann::ordered_json;

std::string read_text_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(ErrorKind::kFileMissing, path, "no such file");
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(st))
    throw InputError(ErrorKind::kFileUnreadable, path, "is a directory, not a file");
  if (std::filesystem::is_character_file(st) || std::filesystem::is_block_file(st))
    throw InputError(ErrorKind::kFileUnreadable, path, "is a device, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(ErrorKind::kFileUnreadable, path,
                     std::string("cannot open for reading: ") + std::strerror(errno));
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw InputError(ErrorKind::kFileUnreadable, path, "read error");
  return buf.str();
}

namespace {

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
      throw InputError(ErrorKind::kUnsupported, source,
                       "sphere-set file version " + std::to_string(v) +
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
  return parse_sphere_set(read_text_file(path), path);
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

namespace {

namespace fs = std::filesystem;

// Follows \p path through symbolic links (relative targets resolve against the link's
// directory) to the file a write should reach, which need not exist. At most 40 links,
// as the kernel allows.
fs::path resolve_links(const std::string& path) {
  fs::path p(path);
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) throw Error(path + ": cannot write: cannot read the symbolic link: " + ec.message());
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  throw InputError(ErrorKind::kWriteFailed, path,
                   "cannot write: too many levels of symbolic links");
}

// The directory a new file at \p p goes into.
fs::path directory_of(const fs::path& p) {
  return p.has_parent_path() ? p.parent_path() : fs::path(".");
}

// Writes \p contents to \p fd, fsyncs it if \p sync, and closes it, whatever failed
// before: the errno of the first step that failed, or 0.
int write_and_close(int fd, const std::string& contents, bool sync) {
  int failure = 0;
  auto step = [&failure](bool done) {
    if (!done && failure == 0) failure = errno != 0 ? errno : EIO;
  };
  std::size_t done = 0;
  while (done < contents.size() && failure == 0) {
    errno = 0;
    const ssize_t n = ::write(fd, contents.data() + done, contents.size() - done);
    if (n < 0 && errno == EINTR) continue;
    step(n > 0);
    if (n > 0) done += static_cast<std::size_t>(n);
  }
  if (sync) step(::fsync(fd) == 0);
  errno = 0;
  step(::close(fd) == 0);
  return failure;
}

// fs::status of \p p, a step towards writing \p path. A missing file or directory
// (ENOENT, ENOTDIR) is not_found, for the caller to judge. Any other failure to look
// \p p up throws: InputError for a path that cannot name a file (a loop of symbolic
// links, a name too long), Error otherwise (no search permission on a directory, an
// I/O error, ...): the real reason, never "does not exist".
fs::file_status status_for_writing(const std::string& path, const fs::path& p) {
  std::error_code ec;
  const fs::file_status st = fs::status(p, ec);
  if (!ec || ec == std::errc::no_such_file_or_directory || ec == std::errc::not_a_directory)
    return st;
  const std::string problem = "cannot write: cannot look up " + p.string() + ": " + ec.message();
  if (ec == std::errc::too_many_symbolic_link_levels || ec == std::errc::filename_too_long)
    throw InputError(ErrorKind::kWriteFailed, path, problem);
  throw Error(path + ": " + problem);
}

// Throws unless the directory \p dir of \p path exists and is a directory.
void check_directory(const std::string& path, const fs::path& dir) {
  const fs::file_status ds = status_for_writing(path, dir);
  if (!fs::exists(ds))
    throw InputError(ErrorKind::kWriteFailed, path,
                     "directory " + dir.string() + " does not exist");
  if (!fs::is_directory(ds))
    throw InputError(ErrorKind::kWriteFailed, path, dir.string() + " is not a directory");
}

// The permission bits a new file gets: 0666 less the process's umask, read from
// /proc/self/status (umask(2) cannot be read without changing it, which would race
// with other threads). 0600 where that is unavailable.
mode_t new_file_mode() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("Umask:", 0) != 0) continue;
    try {
      return static_cast<mode_t>(0666 & ~std::stoul(line.substr(6), nullptr, 8));
    } catch (const std::exception&) {
      break;
    }
  }
  return 0600;
}

// Writes to an existing file that is not a regular one (a character device such as
// /dev/null, a FIFO): in place, as a shell redirection would, since a rename would
// replace the device by a regular file.
void write_in_place(const std::string& path, const fs::path& target, const std::string& contents) {
  const int fd = ::open(target.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw Error(path + ": cannot write: " + std::strerror(errno));
  const int failure = write_and_close(fd, contents, false);
  if (failure != 0) throw Error(path + ": cannot write: " + std::strerror(failure));
}

}  // namespace

void check_output_path(const std::string& path) {
  const fs::path target = resolve_links(path);
  const fs::file_status st = status_for_writing(path, target);
  if (fs::is_directory(st))
    throw InputError(ErrorKind::kWriteFailed, path, "is a directory, not a file");
  if (fs::exists(st)) {
    if (!fs::is_regular_file(st)) {
      if (::access(target.c_str(), W_OK) != 0)
        throw Error(path + ": cannot write: " + std::strerror(errno));
      return;
    }
  }
  const fs::path dir = directory_of(target);
  check_directory(path, dir);
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw Error(path + ": cannot write in directory " + dir.string() + ": " + std::strerror(errno));
}

namespace {

// \p path absolute, links resolved as far as it exists, without a trailing separator.
fs::path resolved(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec);
  fs::path r = fs::weakly_canonical(p, ec);
  if (ec) r = p.lexically_normal();
  return r.filename().empty() ? r.parent_path() : r;
}

}  // namespace

void check_output_spares_inputs(const std::string& output, const std::vector<std::string>& inputs) {
  if (output.empty()) return;
  const fs::path out = resolved(output);
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    const fs::path in = resolved(input);
    if (std::mismatch(out.begin(), out.end(), in.begin(), in.end()).first == out.end())
      throw InputError::option(ErrorKind::kConflict, "output", output,
                               (in == out ? "is the input " : output + " holds the input ") +
                                   input +
                                   ", which writing it would overwrite or remove: choose "
                                   "another path");
  }
}

// The temporary file is created by this call with O_EXCL, so an existing file or symbolic
// link at its name is never written through, and it gets its final permission bits
// before any contents are written, so the contents are never readable more widely than
// the file they replace. A file that is not regular (a character device such as
// /dev/null, a FIFO) is written in place, as a shell redirection would: renaming over it
// would replace the device by a regular file.
void write_file_atomically(const std::string& path, const std::string& contents) {
  const fs::path target = resolve_links(path);
  const fs::file_status st = status_for_writing(path, target);
  if (fs::is_directory(st))
    throw InputError(ErrorKind::kWriteFailed, path, "is a directory, not a file");
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    write_in_place(path, target, contents);
    return;
  }
  const fs::path dir = directory_of(target);
  check_directory(path, dir);

  // The temporary file is made by this call alone (O_EXCL: never an existing file, nor
  // one a symbolic link points to) and readable by its owner only until it has the
  // final permission bits: those of the file it replaces, or a new file's default. Only
  // then are the contents written.
  const mode_t mode =
      fs::is_regular_file(st) ? static_cast<mode_t>(st.permissions()) & 07777 : new_file_mode();
  static std::atomic_uint counter{0};  // two writers in one process never share a name
  fs::path tmp;
  int fd = -1;
  for (int attempt = 0; attempt < 1000 && fd < 0; ++attempt) {
    tmp = dir / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                 std::to_string(counter++));
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0 && errno != EEXIST) break;  // a name that exists: try the next one
  }
  if (fd < 0) throw Error(path + ": cannot write: " + std::strerror(errno));
  int failure = 0;
  if (::fchmod(fd, mode) != 0) {
    failure = errno;
    ::close(fd);
  } else {
    failure = write_and_close(fd, contents, true);
  }
  std::error_code ec;
  if (failure != 0) {
    fs::remove(tmp, ec);
    throw Error(path + ": cannot write: " + std::strerror(failure));
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(path + ": cannot write: " + ec.message());
  }
}

}  // namespace medspheres
