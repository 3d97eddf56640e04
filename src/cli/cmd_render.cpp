// medspheres render MESH SPHERES -o out.png: a picture of a sphere set over its mesh.
#include <iostream>
#include <memory>
#include <regex>
#include <string>

#include "cli_common.h"
#include "medspheres/error.h"
#include "medspheres/io.h"
#include "medspheres/mesh/mesh_io.h"
#include "medspheres/render/png_write.h"
#include "medspheres/render/render.h"

namespace medspheres::cli {

namespace {

struct RenderArgs {
  std::string mesh;
  std::string spheres;
  std::string output;
  std::string view = "iso";
  std::string size = "1024x768";
  int threads = 0;
  double tolerance = 0.005;
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

int run_render(const RenderArgs& args) {
  render::RenderOptions options;
  options.view = render::parse_view(args.view);
  parse_size(args.size, options);
  options.threads = args.threads;
  try {
    check_output_path(args.output);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError("-o", e.what());  // an output that cannot be written is bad usage
  }
  const LoadedMesh loaded = load_mesh(args.mesh);
  for (const std::string& w : loaded.warnings)
    std::cerr << "medspheres: warning: " << args.mesh << ": " << w << "\n";
  const SphereSet set = load_sphere_set(args.spheres);
  if (!(args.tolerance >= 0.0) || !std::isfinite(args.tolerance))
    throw InputError("--tolerance", "must be a finite number >= 0");
  options.protrusion_tolerance = args.tolerance * loaded.report.largest_side();
  const render::RayScene scene(loaded.mesh, set, args.threads);
  const render::Rendering r = render::render(scene, options);
  if (!r.mismatch.empty())
    std::cerr << "medspheres: warning: " << args.spheres << " over " << args.mesh << ": "
              << r.mismatch << "\n";
  const std::string text = render::legend(scene, options, r.counts);
  render::write_png(args.output, r.image,
                    {{"Software", "medspheres render"},
                     {"Source", args.mesh + " " + args.spheres},
                     {"Description", text}});
  std::cout << text << "\n";
  return kExitOk;
}

}  // namespace

Runner register_render(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* sub = app.add_subcommand(
      "render", "Draw a sphere set over its mesh to a PNG (headless ray casting)");
  sub->add_option("mesh", args->mesh, "Mesh file (as bake reads it)")->required();
  sub->add_option("spheres", args->spheres, "Sphere-set file (.json)")->required();
  sub->add_option("-o,--output", args->output, "PNG file to write")->required();
  sub->add_option("--view", args->view, "iso, front, side, top or grid (the four in one)")
      ->capture_default_str();
  sub->add_option("--size", args->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  sub->add_option("--tolerance", args->tolerance,
                  "Caps outside the solid by at most this fraction of the mesh box's largest "
                  "side are not drawn as sticking out")
      ->capture_default_str();
  sub->add_option("--threads", args->threads, "Threads (0: all cores)")->capture_default_str();
  return [args] { return run_render(*args); };
}

}  // namespace medspheres::cli
