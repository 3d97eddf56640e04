#include "medspheres/render/render.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "medspheres/number_text.h"
#include "medspheres/threads.h"

namespace medspheres::render {

namespace {

using Color = Eigen::Vector3d;  // components in [0, 1]

Color color(const Rgb& c) {
  return Color(c[0], c[1], c[2]) / 255.0;
}

// Lambert shading under a light from behind the viewer's upper left shoulder.
Color shade(const Rgb& base, const Eigen::Vector3d& normal, const Eigen::Vector3d& light) {
  return color(base) * (0.35 + 0.65 * std::abs(normal.dot(light)));
}

struct Tile {
  OrthoCamera camera;
  int x0 = 0, y0 = 0;  ///< position in the image
};

// The colour of one ray, and its contribution to the counts.
Color pixel_color(const RayHit& hit, bool beyond_tolerance, const Palette& pal,
                  const Eigen::Vector3d& light, PixelCounts& counts) {
  const bool mesh = hit.triangle >= 0, ball = hit.sphere >= 0;
  counts.mesh += mesh;
  counts.spheres += ball;
  if (!mesh && !ball) {
    ++counts.background;
    return color(pal.background);
  }
  const bool protruding = ball && !hit.sphere_inside_solid() && beyond_tolerance;
  counts.protruding += protruding;
  const Color sphere_c =
      ball ? shade(protruding ? pal.protruding : pal.inside, hit.sphere_normal, light) : Color();
  if (mesh && hit.mesh_t < hit.sphere_t) {
    // Crossed before any ball: that surface point lies outside every ball.
    ++counts.uncovered;
    const Color mesh_c = shade(pal.uncovered, hit.mesh_normal, light);
    const Color behind = ball ? sphere_c : color(pal.background);
    return pal.uncovered_alpha * mesh_c + (1.0 - pal.uncovered_alpha) * behind;
  }
  if (!mesh) return pal.cap_alpha * sphere_c + (1.0 - pal.cap_alpha) * color(pal.background);
  const Color mesh_c = shade(pal.mesh, hit.mesh_normal, light);
  if (protruding) return pal.cap_alpha * sphere_c + (1.0 - pal.cap_alpha) * mesh_c;
  return pal.mesh_alpha * mesh_c + (1.0 - pal.mesh_alpha) * sphere_c;
}

void render_tile(const RayScene& scene, const Tile& tile, const RenderOptions& options, int threads,
                 Image& image, PixelCounts& total) {
  const OrthoCamera& cam = tile.camera;
  const double tolerance = options.protrusion_tolerance;
  const Eigen::Vector3d light = (-cam.forward + 0.35 * cam.up - 0.25 * cam.right).normalized();
  std::size_t mesh = 0, uncovered = 0, spheres = 0, protruding = 0, background = 0;
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads) \
    reduction(+ : mesh, uncovered, spheres, protruding, background)
  for (int y = 0; y < cam.height; ++y) {
    PixelCounts row;
    std::uint8_t* out = &image.rgb[3 * ((std::size_t(tile.y0) + y) * image.width + tile.x0)];
    for (int x = 0; x < cam.width; ++x) {
      const Eigen::Vector3d origin = cam.ray_origin(x, y);
      const RayHit hit = scene.trace(origin, cam.forward);
      const bool beyond = tolerance <= 0.0 || hit.sphere < 0 || hit.sphere_inside_solid() ||
                          scene.distance_to_mesh(origin + hit.sphere_t * cam.forward) > tolerance;
      const Color c = pixel_color(hit, beyond, options.palette, light, row);
      for (int k = 0; k < 3; ++k)
        out[3 * x + k] = static_cast<std::uint8_t>(std::lround(std::clamp(c[k], 0.0, 1.0) * 255));
    }
    mesh += row.mesh, uncovered += row.uncovered, spheres += row.spheres;
    protruding += row.protruding, background += row.background;
  }
  total.mesh += mesh, total.uncovered += uncovered, total.spheres += spheres;
  total.protruding += protruding, total.background += background;
}

// Boxes: the mesh's triangles' (m) and the balls' (s).
std::string box_mismatch(const Eigen::Vector3d& m_lo, const Eigen::Vector3d& m_hi,
                         const Eigen::Vector3d& s_lo, const Eigen::Vector3d& s_hi) {
  const Eigen::Vector3d lo = m_lo.cwiseMax(s_lo);
  const Eigen::Vector3d hi = m_hi.cwiseMin(s_hi);
  const double mesh_size = (m_hi - m_lo).norm();
  const double sphere_size = (s_hi - s_lo).norm();
  std::ostringstream w;
  if ((hi - lo).minCoeff() < 0.0)
    w << "the sphere set's bounding box does not overlap the mesh's: are they in the same "
         "frame and units?";
  else if (sphere_size > 10.0 * mesh_size || mesh_size > 10.0 * sphere_size)
    w << "the sphere set's bounding box is " << number_text(sphere_size / mesh_size)
      << " times the mesh's in size: are they in the same units?";
  return w.str();
}

}  // namespace

Rgb Image::at(int x, int y) const {
  const std::size_t i = 3 * (std::size_t(y) * width + x);
  return {rgb.at(i), rgb.at(i + 1), rgb.at(i + 2)};
}

Rendering render(const RayScene& scene, const RenderOptions& options) {
  const int w = options.width, h = options.height;
  if (w < 1 || h < 1 || w > 16384 || h > 16384)
    throw std::invalid_argument("render: the size must be 1 .. 16384 pixels each way");
  if (options.view == View::grid && (w < 2 || h < 2))
    throw std::invalid_argument("render: a grid needs at least 2 x 2 pixels");
  if (!(options.protrusion_tolerance >= 0.0) || !std::isfinite(options.protrusion_tolerance))
    throw std::invalid_argument("render: protrusion_tolerance must be finite and >= 0");
  const int threads = thread_count(options.threads);
  Rendering r;
  if (scene.num_triangles() > 0 && scene.num_spheres() > 0)
    r.mismatch =
        box_mismatch(scene.mesh_lo(), scene.mesh_hi(), scene.spheres_lo(), scene.spheres_hi());
  Eigen::Vector3d lo = scene.mesh_lo().cwiseMin(scene.spheres_lo());
  Eigen::Vector3d hi = scene.mesh_hi().cwiseMax(scene.spheres_hi());
  if ((hi - lo).minCoeff() < 0.0) lo = hi = Eigen::Vector3d::Zero();  // nothing at all
  r.image.width = w;
  r.image.height = h;
  r.image.rgb.assign(std::size_t(3) * w * h, 0);
  std::vector<Tile> tiles;
  if (options.view != View::grid) {
    tiles.push_back({frame_camera(options.view, lo, hi, w, h), 0, 0});
  } else {
    const View views[4] = {View::iso, View::front, View::side, View::top};
    for (int k = 0; k < 4; ++k) {
      const int x0 = (k % 2) * (w / 2), y0 = (k / 2) * (h / 2);
      const int tw = k % 2 ? w - w / 2 : w / 2, th = k / 2 ? h - h / 2 : h / 2;
      tiles.push_back({frame_camera(views[k], lo, hi, tw, th), x0, y0});
    }
  }
  for (const Tile& tile : tiles) render_tile(scene, tile, options, threads, r.image, r.counts);
  return r;
}

std::string mismatch_warning(const TriangleMesh& mesh, const SphereSet& spheres) {
  if (mesh.triangles.empty() || spheres.spheres.empty()) return {};
  Eigen::Vector3d m_lo = Eigen::Vector3d::Constant(HUGE_VAL), m_hi = -m_lo;
  Eigen::Vector3d s_lo = m_lo, s_hi = m_hi;
  for (const auto& t : mesh.triangles)
    for (int k : t)
      m_lo = m_lo.cwiseMin(mesh.vertices.at(k)), m_hi = m_hi.cwiseMax(mesh.vertices.at(k));
  for (const Sphere& s : spheres.spheres) {
    s_lo = s_lo.cwiseMin(s.center - Eigen::Vector3d::Constant(s.radius));
    s_hi = s_hi.cwiseMax(s.center + Eigen::Vector3d::Constant(s.radius));
  }
  return box_mismatch(m_lo, m_hi, s_lo, s_hi);
}

std::string legend(const RayScene& scene, const RenderOptions& options, const PixelCounts& c) {
  const auto percent = [](std::size_t part, std::size_t whole) {
    return whole == 0 ? std::string("0") : number_text(100.0 * double(part) / double(whole));
  };
  std::ostringstream s;
  s << "view " << to_string(options.view) << ", " << options.width << "x" << options.height
    << "; mesh: " << scene.num_triangles() << " triangles; spheres: " << scene.num_spheres()
    << "\nuncovered surface (red): " << c.uncovered << " of " << c.mesh << " mesh pixels ("
    << percent(c.uncovered, c.mesh) << " %)"
    << "\ncaps outside the solid by more than " << number_text(options.protrusion_tolerance)
    << " (orange): " << c.protruding << " of " << c.spheres << " sphere pixels ("
    << percent(c.protruding, c.spheres) << " %)";
  return s.str();
}

}  // namespace medspheres::render
