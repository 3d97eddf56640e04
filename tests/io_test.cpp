#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/io.h"
#include "support/temp_dir.h"

using Catch::Matchers::Contains;
using medspheres::InputError;
using medspheres::Sphere;
using medspheres::SphereSet;
using medspheres::test::read_file;
using medspheres::test::TempDir;

namespace {

SphereSet random_set(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1e3, 1e3), r(1e-9, 10.0);
  SphereSet s;
  for (std::size_t i = 0; i < n; ++i) s.spheres.push_back({{u(rng), u(rng), u(rng)}, r(rng)});
  return s;
}

// Loads \p text from a file and returns the InputError message (or "" if none).
std::string load_error(const TempDir& dir, const std::string& text) {
  const std::string path = dir.write("bad.spheres.json", text);
  try {
    medspheres::load_sphere_set(path);
  } catch (const InputError& e) {
    CHECK(e.source() == path);
    CHECK_THAT(std::string(e.what()), Contains(path));
    return e.problem();
  }
  return "";
}

}  // namespace

TEST_CASE("sphere set files round-trip bit-identical, metadata included", "[io]") {
  TempDir dir;
  SphereSet s = random_set(500, 7);
  s.spheres.push_back({{0.1, -0.0, 1e-300}, std::numeric_limits<double>::denorm_min()});
  s.metadata_json =
      R"({"source":{"mesh":"a.stl","triangles":12},"stats":{"nerr":0.03},"x-unknown":[1,2,{"k":null}]})";
  const std::string path = dir.file("a.spheres.json");
  medspheres::save_sphere_set(s, path);
  const SphereSet t = medspheres::load_sphere_set(path);
  REQUIRE(t.size() == s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    // Bitwise equality, not approximate: the writer must print enough digits.
    CHECK(std::memcmp(&t.spheres[i].radius, &s.spheres[i].radius, sizeof(double)) == 0);
    for (int k = 0; k < 3; ++k) CHECK(t.spheres[i].center[k] == s.spheres[i].center[k]);
  }
  CHECK(t.metadata_json == s.metadata_json);
  // And saving again produces the same bytes.
  CHECK(medspheres::sphere_set_to_json(t) == medspheres::sphere_set_to_json(s));
}

TEST_CASE("a reader needs only the spheres key and ignores unknown keys", "[io]") {
  const SphereSet s = medspheres::parse_sphere_set(
      R"({"spheres": [[1, 2, 3, 0.5]], "future": {"anything": true}})", "inline");
  REQUIRE(s.size() == 1);
  CHECK(s.spheres[0].center == Eigen::Vector3d(1, 2, 3));
  CHECK(s.spheres[0].radius == 0.5);
  CHECK_THAT(s.metadata_json, Contains("future"));
}

TEST_CASE("malformed sphere files are rejected with the file and the problem", "[io]") {
  TempDir dir;
  CHECK_THAT(load_error(dir, "{not json"), Contains("not valid JSON"));
  CHECK_THAT(load_error(dir, "[1, 2]"), Contains("not a JSON object"));
  CHECK_THAT(load_error(dir, R"({"format": "medspheres.sphere_set"})"), Contains("\"spheres\""));
  CHECK_THAT(load_error(dir, R"({"spheres": 3})"), Contains("not an array"));
  CHECK_THAT(load_error(dir, R"({"spheres": [[1, 2, 3]]})"), Contains("sphere 0"));
  CHECK_THAT(load_error(dir, R"({"spheres": [[1, 2, 3, 1], [1, 2, "x", 1]]})"),
             Contains("sphere 1: z is not a number"));
  CHECK_THAT(load_error(dir, R"({"spheres": [[1, 2, 3, -1]]})"), Contains("radius -1"));
  CHECK_THAT(load_error(dir, R"({"spheres": [[1, 2, 3, 0]]})"), Contains("radius 0"));
  CHECK_THAT(load_error(dir, R"({"spheres": [[1e999, 2, 3, 1]]})"), Contains("overflow"));
  CHECK_THAT(load_error(dir, R"({"spheres": [[NaN, 2, 3, 1]]})"), Contains("not valid JSON"));
  CHECK_THAT(load_error(dir, R"({"format": "other", "spheres": []})"), Contains("\"format\""));
  CHECK_THAT(load_error(dir, R"({"version": 2, "spheres": []})"), Contains("version 2"));
  CHECK_THAT(load_error(dir, ""), Contains("not valid JSON"));
}

TEST_CASE("a missing sphere file names the path", "[io]") {
  TempDir dir;
  const std::string path = dir.file("nope.spheres.json");
  CHECK_THROWS_WITH(medspheres::load_sphere_set(path), Contains(path) && Contains("no such file"));
  CHECK_THROWS_WITH(medspheres::load_sphere_set(dir.path().string()), Contains("directory"));
}

TEST_CASE("a device is not read as a file", "[io]") {
  // /dev/zero would be read for ever; /dev/null is a device too.
  TempDir dir;
  const std::string zero = dir.file("zero.json");
  std::filesystem::create_symlink("/dev/zero", zero);
  for (const std::string& path : {zero, std::string("/dev/null")}) {
    INFO(path);
    CHECK_THROWS_WITH(medspheres::read_text_file(path), Contains(path) && Contains("is a device"));
    CHECK_THROWS_AS(medspheres::load_sphere_set(path), InputError);
  }
}

TEST_CASE("an output may not be, nor hold, one of the inputs", "[io]") {
  TempDir dir;
  std::filesystem::create_directory(dir.file("in"));
  const std::string input = dir.write("in/a.json", "{}");
  std::filesystem::create_symlink(input, dir.file("link.json"));
  std::filesystem::create_symlink(dir.file("in"), dir.file("in_link"));
  auto problem = [&](const std::string& out) -> std::string {
    try {
      medspheres::check_output_spares_inputs(out, {"", dir.file("other.json"), input});
    } catch (const InputError& e) {
      CHECK(e.field() == "output");
      CHECK(e.value() == out);
      return e.problem();
    }
    return "";
  };
  CHECK_THAT(problem(input), Contains("is the input " + input));
  CHECK_THAT(problem(dir.file("link.json")), Contains("is the input"));  // the same file
  CHECK_THAT(problem(dir.file("in")), Contains(dir.file("in") + " holds the input " + input));
  CHECK_THAT(problem(dir.file("in") + "/"), Contains("holds the input"));
  CHECK_THAT(problem(dir.file("in_link")), Contains("holds the input"));  // a link to it
  CHECK_THAT(problem(dir.path().string()), Contains("holds the input"));
  CHECK(problem(dir.file("in/b.json")).empty());  // beside it
  CHECK(problem(dir.file("in2")).empty());        // a name that starts the same
  CHECK(problem(dir.file("new/out")).empty());    // not there yet
  CHECK(problem("").empty());
}

TEST_CASE("saving is atomic: failures leave no file and no temporary behind", "[io]") {
  TempDir dir;
  SphereSet good = random_set(3, 1);
  const std::string path = dir.file("out.spheres.json");
  medspheres::save_sphere_set(good, path);
  const std::string before = medspheres::sphere_set_to_json(good);

  // An invalid set is refused before anything is written; the old file survives.
  SphereSet bad = good;
  bad.spheres[1].radius = -2.0;
  CHECK_THROWS_AS(medspheres::save_sphere_set(bad, path), InputError);
  CHECK(read_file(path) == before);

  // A directory that does not exist: an error, and nothing created.
  CHECK_THROWS_AS(medspheres::save_sphere_set(good, dir.file("missing/out.json")),
                  medspheres::Error);
  std::size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
    (void)e;
    ++entries;
  }
  CHECK(entries == 1);  // only out.spheres.json
}

TEST_CASE("saving through a symbolic link writes its target and keeps the link", "[io]") {
  namespace fs = std::filesystem;
  TempDir dir;
  const SphereSet s = random_set(4, 3);
  const std::string expected = medspheres::sphere_set_to_json(s);
  fs::create_directories(dir.path() / "real");
  const std::string target = dir.write("real/target.json", "old");
  fs::permissions(target, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);

  // An absolute link, a relative one, and a link to a link.
  const fs::path absolute = dir.path() / "absolute.json";
  const fs::path relative = dir.path() / "relative.json";
  const fs::path chain = dir.path() / "chain.json";
  fs::create_symlink(target, absolute);
  fs::create_symlink("real/target.json", relative);
  fs::create_symlink("absolute.json", chain);
  for (const fs::path& link : {absolute, relative, chain}) {
    INFO(link.string());
    fs::remove(target);
    std::ofstream(target) << "old";
    fs::permissions(target, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
    medspheres::save_sphere_set(s, link.string());
    CHECK(fs::is_symlink(fs::symlink_status(link)));
    CHECK(fs::is_regular_file(fs::symlink_status(target)));
    CHECK(read_file(target) == expected);
    CHECK(read_file(link.string()) == expected);
    // The file replaced keeps its permission bits.
    CHECK((fs::status(target).permissions() & fs::perms::all) ==
          (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
  }
  // A dangling link: its target is created, the link stays.
  const fs::path dangling = dir.path() / "dangling.json";
  fs::create_symlink("real/new.json", dangling);
  medspheres::save_sphere_set(s, dangling.string());
  CHECK(fs::is_symlink(fs::symlink_status(dangling)));
  CHECK(read_file((dir.path() / "real/new.json").string()) == expected);
  // Only the files made here remain: no temporaries.
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.path() / "real")) {
    (void)e;
    ++entries;
  }
  CHECK(entries == 2);
  // A loop of links is an error naming the path.
  fs::create_symlink("loop_b.json", dir.path() / "loop_a.json");
  fs::create_symlink("loop_a.json", dir.path() / "loop_b.json");
  CHECK_THROWS_WITH(medspheres::save_sphere_set(s, (dir.path() / "loop_a.json").string()),
                    Contains("loop_a.json") && Contains("symbolic links"));
}

TEST_CASE("saving to a device writes it in place and leaves it a device", "[io]") {
  // Renaming a temporary file over /dev/null would replace it, as root, by a regular file.
  const SphereSet s = random_set(2, 4);
  struct stat before {};
  REQUIRE(::stat("/dev/null", &before) == 0);
  REQUIRE(S_ISCHR(before.st_mode));
  medspheres::save_sphere_set(s, "/dev/null");
  medspheres::check_output_path("/dev/null");
  struct stat after {};
  REQUIRE(::stat("/dev/null", &after) == 0);
  CHECK(S_ISCHR(after.st_mode));
  CHECK(after.st_rdev == before.st_rdev);
  CHECK(after.st_ino == before.st_ino);
  // A device that fails the write (/dev/full: no space left) is an Error, not bad input.
  struct stat full {};
  if (::stat("/dev/full", &full) == 0 && S_ISCHR(full.st_mode)) {
    try {
      medspheres::save_sphere_set(s, "/dev/full");
      FAIL("writing to /dev/full must fail");
    } catch (const InputError&) {
      FAIL("a failed write is not bad input");
    } catch (const medspheres::Error& e) {
      CHECK_THAT(std::string(e.what()), Contains("/dev/full") && Contains("cannot write"));
    }
    REQUIRE(::stat("/dev/full", &full) == 0);
    CHECK(S_ISCHR(full.st_mode));
  }
}

TEST_CASE("an output path that cannot be a file is bad input, found before writing", "[io]") {
  TempDir dir;
  const SphereSet s = random_set(2, 5);
  const std::string parent_file = dir.write("plain", "x");
  struct Case {
    std::string path, says;
  };
  for (const Case& c : {Case{dir.path().string(), "is a directory"},
                        Case{dir.file("missing/out.json"), "does not exist"},
                        Case{parent_file + "/out.json", "is not a directory"}}) {
    INFO(c.path);
    CHECK_THROWS_WITH(medspheres::check_output_path(c.path), Contains(c.path) && Contains(c.says));
    try {
      medspheres::save_sphere_set(s, c.path);
      FAIL("must throw");
    } catch (const InputError& e) {
      CHECK(e.source() == c.path);
      CHECK_THAT(e.problem(), Contains(c.says));
    }
  }
  CHECK(std::filesystem::is_directory(dir.path()));
  CHECK(read_file(parent_file) == "x");
  CHECK_NOTHROW(medspheres::check_output_path(dir.file("new.json")));
  CHECK_FALSE(std::filesystem::exists(dir.file("new.json")));
}

TEST_CASE("sphere files: subnormal radii are valid, a box beyond the doubles is not", "[io]") {
  const SphereSet tiny = medspheres::parse_sphere_set(R"({"spheres": [[0, 0, 0, 1e-320]]})", "t");
  CHECK(tiny.spheres[0].radius == 1e-320);
  CHECK_THROWS_WITH(
      medspheres::parse_sphere_set(R"({"spheres": [[0, 0, 0, 1], [1e308, 0, 0, 1e308]]})", "t"),
      Contains("sphere 1") && Contains("beyond the largest finite double"));
}

namespace {

// What check_output_path and then save_sphere_set throw for \p path, one line each:
// "input: <what>" for an InputError, "error: <what>" for another Error, "none".
std::string write_outcomes(const std::string& path) {
  std::string out;
  for (int call = 0; call < 2; ++call) {
    try {
      if (call == 0)
        medspheres::check_output_path(path);
      else
        medspheres::save_sphere_set(random_set(1, 6), path);
      out += "none\n";
    } catch (const InputError& e) {
      out += std::string("input: ") + e.what() + "\n";
    } catch (const medspheres::Error& e) {
      out += std::string("error: ") + e.what() + "\n";
    }
  }
  return out;
}

// write_outcomes(path) as user and group nobody (65534), in a child process: root may
// search any directory. Empty when the child cannot drop its privileges.
std::string write_outcomes_as_nobody(const std::string& path) {
  int fds[2];
  REQUIRE(::pipe(fds) == 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    if (::setgid(65534) == 0 && ::setuid(65534) == 0) {
      const std::string out = write_outcomes(path);
      if (::write(fds[1], out.data(), out.size()) < 0) ::_exit(1);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  REQUIRE(pid > 0);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return out;
}

}  // namespace

TEST_CASE("a directory that cannot be searched is an error and not a missing one", "[io]") {
  namespace fs = std::filesystem;
  TempDir dir;
  const fs::path locked = dir.path() / "locked";
  fs::create_directories(locked / "sub");
  const std::string path = (locked / "sub" / "out.json").string();
  fs::permissions(locked, fs::perms::none);
  const std::string outcomes =
      ::geteuid() == 0 ? write_outcomes_as_nobody(path) : write_outcomes(path);
  fs::permissions(locked, fs::perms::owner_all);
  if (outcomes.empty()) {
    WARN("cannot run as nobody: not checked");
    return;
  }
  const std::string want = "error: " + path + ": cannot write: cannot look up ";
  INFO(outcomes);
  CHECK_THAT(outcomes, Contains(want) && Contains("Permission denied") &&
                           !Contains("does not exist") && !Contains("input:") && !Contains("none"));
  CHECK_FALSE(fs::exists(locked / "sub" / "out.json"));
}

TEST_CASE("the temporary file is always created anew and no existing file or link is written",
          "[io]") {
  namespace fs = std::filesystem;
  TempDir dir;
  const SphereSet s = random_set(3, 7);
  const std::string victim = dir.write("victim.txt", "victim");
  const std::string target = dir.file("out.json");
  // A link at each of the first names the temporary file can take (write_file_atomically
  // names it .NAME.tmp.PID.N): each must be passed by, not written through.
  constexpr int kLinks = 256;
  for (int i = 0; i < kLinks; ++i)
    fs::create_symlink(victim, dir.path() / (".out.json.tmp." + std::to_string(::getpid()) + "." +
                                             std::to_string(i)));
  medspheres::save_sphere_set(s, target);
  CHECK(read_file(victim) == "victim");
  CHECK(fs::is_regular_file(fs::symlink_status(target)));
  CHECK(read_file(target) == medspheres::sphere_set_to_json(s));
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    (void)e;
    ++entries;
  }
  CHECK(entries == kLinks + 2);  // the links, the victim and the output: no temporary
}

TEST_CASE("a new file gets 0666 less the umask and a replaced one keeps its bits", "[io]") {
  namespace fs = std::filesystem;
  TempDir dir;
  const SphereSet s = random_set(2, 8);
  const auto bits = [](const std::string& p) {
    return static_cast<unsigned>(fs::status(p).permissions() & fs::perms::all);
  };
  for (const unsigned mask : {022u, 027u, 077u}) {
    INFO("umask " << mask);
    const std::string path = dir.file("new" + std::to_string(mask) + ".json");
    const mode_t old = ::umask(static_cast<mode_t>(mask));
    medspheres::save_sphere_set(s, path);
    ::umask(old);
    CHECK(bits(path) == (0666u & ~mask));
    // Replaced under another umask: the bits stay.
    fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write | fs::perms::others_read);
    medspheres::save_sphere_set(s, path);
    CHECK(bits(path) == 0604u);
  }
}
