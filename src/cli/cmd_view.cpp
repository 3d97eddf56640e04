// medspheres view MESH SPHERES -o out.html: a self-contained HTML viewer (three.js inlined).
#include <iostream>
#include <memory>
#include <string>

#include "cli_common.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/render/view_html.h"
#include "medspheres/thread_option.h"
#include "scene_input.h"

namespace medspheres::cli {

namespace {

struct ViewArgs {
  SceneArgs scene;
  std::string output;
  int depth = 5;
  int threads = 0;
};

int run_view(const ViewArgs& args) {
  if (args.depth < 0 || args.depth > 10) throw InputError("--cover-depth", "must be 0 .. 10");
  check_threads_option(args.threads, "threads");
  check_scene_output(args.output, args.scene);
  const SceneInput in = load_scene_input(args.scene);
  if (!in.mismatch.empty())
    std::cerr << "medspheres: warning: " << in.source << ": " << in.mismatch << "\n";
  render::ViewOptions options;
  options.title = "medspheres view: " + in.source;
  options.warning = in.mismatch;
  options.cover_depth = args.depth;
  options.threads = args.threads;
  const std::string page = render::view_html(in.scene, options);
  write_file_atomically(args.output, page);
  std::size_t triangles = 0, inner = 0, outer = 0;
  for (const render::ScenePart& p : in.scene.parts)
    triangles += p.mesh.num_triangles(), inner += p.inner.size(), outer += p.outer.size();
  std::cout << "wrote " << args.output << ": " << count_text(in.scene.parts.size(), "part") << ", "
            << count_text(triangles, "triangle") << ", " << inner << " inner and "
            << count_text(outer, "outer sphere") << " (" << count_text(page.size(), "byte")
            << ")\n";
  return kExitOk;
}

}  // namespace

Runner register_view(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* sub = app.add_subcommand(
      "view",
      "Write a self-contained HTML viewer (three.js, opens from disk) of a sphere set "
      "over its mesh, or of a robot");
  add_scene_options(sub, args->scene);
  sub->add_option("--outer", args->scene.outer,
                  "A mesh's covering set (.json), shown beside SPHERES (the inner set)");
  sub->add_option("-o,--output", args->output, "HTML file to write")->required()->check(non_empty);
  sub->add_option("--cover-depth", args->depth,
                  "Splits of a triangle when certifying which surface the spheres cover (0 .. 10)")
      ->capture_default_str();
  sub->add_option("--threads", args->threads, "Threads (0: all cores)")->capture_default_str();
  return [args] { return run_view(*args); };
}

}  // namespace medspheres::cli
