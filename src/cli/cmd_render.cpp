// medspheres render MESH SPHERES -o out.png: a picture of a sphere set over its mesh, or of
// a robot's link meshes and spheres at a joint vector.
#include <iostream>
#include <memory>
#include <regex>
#include <string>

#include "cli_common.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/render/legend_overlay.h"
#include "medspheres/render/png_write.h"
#include "medspheres/render/render.h"
#include "medspheres/thread_option.h"
#include "scene_input.h"

namespace medspheres::cli {

namespace {

struct RenderArgs {
  SceneArgs scene;
  std::string output;
  std::string view = "iso";
  std::string size = "1024x768";
  std::string set = "auto";
  int threads = 0;
  double tolerance = 0.005;
  bool no_legend = false;
};

// "WxH" with 1 .. 16384 pixels each way.
void parse_size(const std::string& text, render::RenderOptions& options) {
  const std::regex pattern("([0-9]{1,5})x([0-9]{1,5})");
  std::smatch m;
  if (std::regex_match(text, m, pattern)) {
    options.width = std::stoi(m[1]);
    options.height = std::stoi(m[2]);
    const int least = options.view == render::View::grid ? 2 : 1;
    if (options.width >= least && options.height >= least && options.width <= 16384 &&
        options.height <= 16384)
      return;
  }
  throw InputError("--size",
                   "must be WIDTHxHEIGHT, each 1 .. 16384 (2 .. for a grid), got \"" + text + "\"");
}

render::SetChoice parse_set(const std::string& text) {
  if (text == "auto") return render::SetChoice::automatic;
  if (text == "inner") return render::SetChoice::inner;
  if (text == "outer") return render::SetChoice::outer;
  throw InputError("--set", "must be auto, inner or outer, got \"" + text + "\"");
}

// The largest side of the mesh's bounding box (of the spheres' without a mesh).
double largest_side(const TriangleMesh& mesh, const render::RayScene& scene) {
  if (!mesh.triangles.empty()) return (scene.mesh_hi() - scene.mesh_lo()).maxCoeff();
  return scene.num_spheres() > 0 ? (scene.spheres_hi() - scene.spheres_lo()).maxCoeff() : 0.0;
}

int run_render(const RenderArgs& args) {
  render::RenderOptions options;
  options.view = render::parse_view(args.view);
  parse_size(args.size, options);
  check_threads_option(args.threads, "threads");
  options.threads = args.threads;
  const render::SetChoice choice = parse_set(args.set);
  check_scene_output(args.output, args.scene);
  if (!(args.tolerance >= 0.0) || !std::isfinite(args.tolerance))
    throw InputError("--tolerance", "must be a finite number >= 0");
  const SceneInput in = load_scene_input(args.scene);
  const TriangleMesh mesh = render::merged_mesh(in.scene);
  const SphereSet set = render::merged_spheres(in.scene, choice);
  const render::RayScene scene(mesh, set, args.threads);
  options.protrusion_tolerance = args.tolerance * largest_side(mesh, scene);
  render::Rendering r = render::render(scene, options);
  if (!r.mismatch.empty())
    std::cerr << "medspheres: warning: " << in.source << ": " << r.mismatch << "\n";
  const std::string text = render::legend(scene, options, r.counts);
  if (!args.no_legend) render::draw_legend(r.image, text, r.mismatch, options.palette);
  render::write_png(
      args.output, r.image,
      {{"Software", "medspheres render"}, {"Source", in.source}, {"Description", text}});
  std::cout << text << "\n";
  return kExitOk;
}

}  // namespace

Runner register_render(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* sub = app.add_subcommand(
      "render", "Draw a sphere set over its mesh, or a robot, to a PNG (headless ray casting)");
  add_scene_options(sub, args->scene);
  sub->add_option("-o,--output", args->output, "PNG file to write")->required()->check(non_empty);
  sub->add_option("--view", args->view, "iso, front, side, top or grid (the four in one)")
      ->capture_default_str();
  sub->add_option("--size", args->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  sub->add_option("--set", args->set,
                  "A robot's set per link: auto (the outer set where a link has one), inner or "
                  "outer")
      ->capture_default_str();
  sub->add_option("--tolerance", args->tolerance,
                  "Caps outside the solid by at most this fraction of the mesh box's largest "
                  "side are not drawn as sticking out")
      ->capture_default_str();
  sub->add_option("--threads", args->threads, "Threads (0: all cores)")->capture_default_str();
  sub->add_flag("--no-legend", args->no_legend, "Do not draw the legend into the image");
  return [args] { return run_render(*args); };
}

}  // namespace medspheres::cli
