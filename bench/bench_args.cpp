#include "bench_args.h"

#include <cstdlib>

#include <unistd.h>

#include "support/shared_meshes.h"
#include "support/temp_dir.h"

namespace medspheres::bench {

Args::Args(const std::string& name, const std::string& description) : app_(description, name) {}

CLI::Validator Args::not_negative() {
  return CLI::Validator(
      [](std::string& text) {
        return text.find('-') == std::string::npos ? std::string()
                                                   : "must not be negative, got " + text;
      },
      "");
}

CLI::Option* Args::add_meshes(std::string& dir) {
  return add("--meshes", dir, "folder with MANIFEST.tsv")->type_name("DIR");
}

CLI::Option* Args::add_only(std::string& only) {
  return app_.add_option("--only", only, "only meshes whose name contains SUBSTRING")
      ->type_name("SUBSTRING");
}

// CLI11's own exit codes for parse errors run from 100 up; the benchmarks keep the
// project's convention (docs/command-line.md, "Exit codes"): 2 for bad usage.
void Args::parse(int argc, char** argv) {
  try {
    app_.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    std::exit(app_.exit(e));
  } catch (const CLI::ParseError& e) {
    app_.exit(e);
    std::exit(2);
  }
}

bool selected(const std::string& name, const std::string& only) {
  return only.empty() || name.find(only) != std::string::npos;
}

std::vector<MeshFile> bench_meshes(const std::string& dir, bool classic_only) {
  std::vector<MeshFile> out;
  for (const char* file : {"knot1.off", "eight.off"})
    out.push_back({std::string("examples/") + file, test::example_mesh(file)});
  if (!dir.empty())
    for (const test::SharedMesh& m : test::read_manifest(dir))
      if (m.closed && (!classic_only || m.classic())) out.push_back({m.file, m.path});
  return out;
}

void restart_with_passive_openmp(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  setenv("OMP_WAIT_POLICY", "passive", 1);
  execv("/proc/self/exe", argv);  // returns only on failure: go on as we are
}

}  // namespace medspheres::bench
