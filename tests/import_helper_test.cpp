// The isolated import's program (medspheres-import): how load_mesh finds it, what it says
// when it cannot, and imports on many threads at once (the child is spawned, not forked
// from a threaded caller).
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_io.h"
#include "support/mesh_writers.h"
#include "support/temp_dir.h"

using namespace medspheres;
using namespace medspheres::test;
using Catch::Matchers::Contains;

namespace {

constexpr const char* kVariable = "MEDSPHERES_IMPORT_HELPER";

// Sets the variable for its lifetime, then restores what was there.
class ScopedVariable {
 public:
  explicit ScopedVariable(const std::string& value) {
    if (const char* old = std::getenv(kVariable)) old_ = old, had_ = true;
    ::setenv(kVariable, value.c_str(), 1);
  }
  ~ScopedVariable() {
    if (had_)
      ::setenv(kVariable, old_.c_str(), 1);
    else
      ::unsetenv(kVariable);
  }
  ScopedVariable(const ScopedVariable&) = delete;
  ScopedVariable& operator=(const ScopedVariable&) = delete;

 private:
  std::string old_;
  bool had_ = false;
};

// The import program of this build: beside the test program.
std::filesystem::path built_helper() {
  return std::filesystem::read_symlink("/proc/self/exe").parent_path() / "medspheres-import";
}

std::string error_of(const std::string& path) {
  try {
    load_mesh(path);
  } catch (const InputError& e) {
    return std::string("InputError: ") + e.what();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("the import program is found beside the program, or where the variable says",
          "[mesh_io][isolation]") {
  TempDir dir;
  const std::string box = dir.write("box.off", to_off(make_box({1, 2, 3})));
  ::unsetenv(kVariable);
  REQUIRE(std::filesystem::exists(built_helper()));
  CHECK(load_mesh(box).report.signed_volume == Approx(48.0));

  // A wrapper that leaves a mark and runs the real program: the variable is obeyed.
  const std::string mark = dir.file("started");
  const std::string wrapper =
      dir.write("wrapper.sh", "#!/bin/sh\necho started >> '" + mark + "'\nexec '" +
                                  built_helper().string() + "' \"$@\"\n");
  ::chmod(wrapper.c_str(), 0755);
  {
    ScopedVariable use(wrapper);
    CHECK(load_mesh(box).report.signed_volume == Approx(48.0));
    CHECK(load_mesh(box).report.signed_volume == Approx(48.0));
  }
  std::ifstream marks(mark);
  std::string line;
  int starts = 0;
  while (std::getline(marks, line)) starts += line == "started";
  CHECK(starts == 2);
}

TEST_CASE("a variable that names no program is an error naming it, not bad input",
          "[mesh_io][isolation]") {
  TempDir dir;
  const std::string box = dir.write("box.off", to_off(make_box({1, 1, 1})));
  const std::string text = dir.write("not-a-program", "just text\n");
  for (const std::string& bad : {text, dir.file("missing"), dir.path().string()}) {
    INFO(bad);
    ScopedVariable use(bad);
    const std::string message = error_of(box);
    CHECK_THAT(message, !Contains("InputError"));
    CHECK_THAT(message, Contains(box + ": ") && Contains(std::string(kVariable) + "=" + bad) &&
                            Contains("not an executable file"));
  }
  // Without isolation the program is not needed.
  ScopedVariable use(text);
  MeshLoadOptions in_process;
  in_process.isolate_import = false;
  CHECK(load_mesh(box, in_process).report.signed_volume == Approx(8.0));
}

TEST_CASE("imports run on many threads while others allocate and run assimp",
          "[mesh_io][isolation][threads]") {
  // A fork of this process could copy a lock (the allocator's, assimp's, the C++
  // runtime's) that another thread holds, and its child would wait for it until the
  // timeout; a spawned program inherits none.
  TempDir dir;
  const std::string box = dir.write("box.obj", to_obj(make_box({1, 1, 2})));
  std::atomic<bool> stop{false};
  std::atomic<int> good{0}, in_process_good{0};
  std::vector<std::thread> others;
  others.emplace_back([&] {  // the allocator, busy
    while (!stop) {
      std::vector<std::string> v(64, std::string(200, 'x'));
      v.emplace_back(1000, 'y');
    }
  });
  others.emplace_back([&] {  // assimp in this process
    MeshLoadOptions in_process;
    in_process.isolate_import = false;
    while (!stop)
      if (load_mesh(box, in_process).report.signed_volume == Approx(16.0)) ++in_process_good;
  });
  MeshLoadOptions o;
  o.import_timeout_seconds = 120.0;
  std::vector<std::string> errors(4);
  std::vector<std::thread> loaders;
  for (int t = 0; t < 4; ++t)
    loaders.emplace_back([&, t] {
      try {
        for (int i = 0; i < 5; ++i)
          if (load_mesh(box, o).report.signed_volume == Approx(16.0)) ++good;
      } catch (const std::exception& e) {
        errors[t] = e.what();
      }
    });
  for (std::thread& t : loaders) t.join();
  stop = true;
  for (std::thread& t : others) t.join();
  for (const std::string& e : errors) CHECK(e.empty());
  CHECK(good == 20);
  CHECK(in_process_good > 0);
}
