#pragma once
/// \file
/// render(): a picture of a sphere set over its mesh, by orthographic ray casting
/// (RayScene), with the colours below. Per pixel, the first mesh crossing and the first
/// entry into the union of the balls decide:
/// - mesh crossed before any ball: surface no sphere covers (exact: that point lies
///   outside every ball), drawn in `uncovered`; otherwise the mesh in `mesh`;
/// - the ball surface at its entry point is a cap that sticks out of the solid when the
///   mesh's winding number there is <= 0 and its distance to the mesh exceeds
///   protrusion_tolerance (drawn in `protruding`), else `inside`;
/// - the front layer is blended over the one behind: the mesh at mesh_alpha over the
///   spheres it hides, a cap at cap_alpha over the mesh it hides. Lambert shading.
/// The image is the whole scene framed (frame_camera) on the union of both boxes.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "medspheres/render/camera.h"
#include "medspheres/render/ray_scene.h"

namespace medspheres::render {

using Rgb = std::array<std::uint8_t, 3>;

struct Palette {
  Rgb background{255, 255, 255};
  Rgb mesh{175, 175, 170};
  Rgb uncovered{225, 30, 30};
  Rgb inside{60, 110, 220};
  Rgb protruding{245, 165, 20};
  double mesh_alpha = 0.45;       ///< covered mesh over the spheres behind it
  double uncovered_alpha = 0.75;  ///< uncovered mesh over the spheres behind it
  double cap_alpha = 0.55;        ///< sphere cap over the mesh behind it
};

struct RenderOptions {
  View view = View::iso;
  int width = 1024, height = 768;  ///< pixels, each 1 .. 16384
  int threads = 0;                 ///< rows in parallel (threads.h)
  /// A cap outside the solid by at most this length (world units, >= 0) is not counted
  /// as sticking out: a covering or dilated set hugs the surface from outside.
  double protrusion_tolerance = 0.0;
  Palette palette;
};

/// Pixel counts: what the rays met first.
struct PixelCounts {
  std::size_t mesh = 0;        ///< a mesh crossing anywhere on the ray
  std::size_t uncovered = 0;   ///< the mesh crossed before any ball
  std::size_t spheres = 0;     ///< a ball anywhere on the ray (the set's silhouette)
  std::size_t protruding = 0;  ///< the first ball entry outside the solid, beyond tolerance
  std::size_t background = 0;  ///< neither
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< row-major, top row first, 3 bytes a pixel
  Rgb at(int x, int y) const;
};

struct Rendering {
  Image image;
  PixelCounts counts;
  /// The warning for a mesh and a sphere set that do not belong together (boxes that do
  /// not overlap, or sizes a factor 10 apart), or empty.
  std::string mismatch;
};

/// \throws std::invalid_argument for a size outside 1 .. 16384, a bad thread count or a
///   negative or non-finite protrusion_tolerance.
Rendering render(const RayScene& scene, const RenderOptions& options);

/// The warning for a mesh and a sphere set that do not belong together (Rendering::
/// mismatch), or empty.
std::string mismatch_warning(const TriangleMesh& mesh, const SphereSet& spheres);

/// The sentences of the legend: the mesh and set sizes and the pixel counts.
std::string legend(const RayScene& scene, const RenderOptions& options, const PixelCounts& c);

}  // namespace medspheres::render
