#include "spheretree_run.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "medspheres/formats/sph_file.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/sha256.h"

extern char** environ;

namespace medspheres::bench {

namespace {

namespace fs = std::filesystem;

// foam's makeTreeMedial options (spheretree_run.h), with branch k.
std::vector<std::string> foam_options(std::size_t k) {
  return {"-nopause",   "-branch",     std::to_string(k),
          "-depth",     "1",           "-testerLevels",
          "2",          "-numCover",   "5000",
          "-minCover",  "5",           "-initSpheres",
          "1000",       "-minSpheres", "200",
          "-erFact",    "2",           "-maxOptLevel",
          "1",          "-expand",     "-merge",
          "-burst",     "-optimise",   "balance",
          "-balExcess", "0.05"};
}

// The mesh less \p centre as OBJ text, faces as spheretree's loader reads them.
std::string obj_text(const TriangleMesh& mesh, const Eigen::Vector3d& centre) {
  std::string out;
  char line[128];
  for (const Eigen::Vector3d& v : mesh.vertices) {
    const Eigen::Vector3d p = v - centre;
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    out += line;
  }
  for (const auto& t : mesh.triangles) {
    std::snprintf(line, sizeof line, "f %d//%d %d//%d %d//%d\n", t[0] + 1, t[0] + 1, t[1] + 1,
                  t[1] + 1, t[2] + 1, t[2] + 1);
    out += line;
  }
  return out;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
}

// The spheres of level 1 of the .sph \p text, moved by \p centre.
std::vector<Sphere> level_one(const std::string& text, const std::string& source,
                              const Eigen::Vector3d& centre) {
  const std::vector<std::vector<Sphere>> levels = formats::parse_sph_levels(text, source);
  if (levels.size() < 2) return {};
  std::vector<Sphere> s = levels[1];
  for (Sphere& b : s) b.center += centre;
  return s;
}

// Runs \p program with \p args in \p dir, its output to \p log; the exit status, or a
// sentence on how it ended.
std::string run(const std::string& program, const std::vector<std::string>& args,
                const fs::path& log, double& cpu) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(program.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return "cannot start " + program + ": " + std::strerror(rc);
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
        1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  if (WIFSIGNALED(status)) return "crashed (signal " + std::to_string(WTERMSIG(status)) + ")";
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0)
    return "exit status " + std::to_string(WEXITSTATUS(status));
  return "";
}

}  // namespace

SpheretreeRun run_spheretree(const std::string& bin_dir, const TriangleMesh& mesh, std::size_t k,
                             const std::string& cache_dir, const std::string& work_dir,
                             bool cached_only) {
  const Eigen::Vector3d centre = mesh.bounds().center();
  const std::string obj = obj_text(mesh, centre);
  const std::vector<std::string> options = foam_options(k);
  std::string key_text = obj;
  for (const std::string& o : options) key_text += " " + o;
  const std::string key = sha256_hex(key_text).substr(0, 24);
  SpheretreeRun out;
  const fs::path cached = cache_dir.empty() ? fs::path() : fs::path(cache_dir) / key;
  if (!cache_dir.empty() && fs::exists(cached.string() + ".txt")) {
    std::istringstream t(read_text(cached.string() + ".txt"));
    t >> out.seconds >> out.cpu;
    std::getline(t >> std::ws, out.error);
    out.cached = true;
    if (out.error.empty())
      out.spheres =
          level_one(read_text(cached.string() + ".sph"), cached.string() + ".sph", centre);
    return out;
  }
  if (cached_only) {
    out.skipped = true;
    return out;
  }
  fs::create_directories(work_dir);
  const fs::path input = fs::path(work_dir) / (key + ".obj");
  const fs::path sph = fs::path(work_dir) / (key + "-medial.sph");
  write_text(input, obj);
  fs::remove(sph);
  std::vector<std::string> args = options;
  args.push_back(input.string());
  const auto start = std::chrono::steady_clock::now();
  out.error = run((fs::path(bin_dir) / "makeTreeMedial").string(), args,
                  fs::path(work_dir) / (key + ".log"), out.cpu);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (out.error.empty() && !fs::exists(sph)) out.error = "wrote no .sph";
  std::string text;
  if (out.error.empty()) {
    text = read_text(sph);
    out.spheres = level_one(text, sph.string(), centre);
    if (out.spheres.empty()) out.error = "no spheres on level 1";
  }
  if (!cache_dir.empty()) {
    fs::create_directories(cache_dir);
    if (out.error.empty()) write_text(cached.string() + ".sph", text);
    std::ostringstream t;
    t.precision(17);
    t << out.seconds << " " << out.cpu << " " << out.error << "\n";
    write_text(cached.string() + ".txt", t.str());
  }
  fs::remove(input);
  fs::remove(sph);
  return out;
}

}  // namespace medspheres::bench
