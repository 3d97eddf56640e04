#pragma once
/// \file
/// The solid of a link: the union of its geometry elements, as triangle meshes placed in
/// the link frame, and its sphere primitives, which are kept exactly.
///
/// Frames and units as in urdf_robot.h: a part's mesh is in its element frame G (scale
/// applied: v -> S v), and LinkSolidPart::origin = X_LG places it in the link frame L.
/// A scale with a negative product mirrors the mesh; its triangles are then reversed, so
/// that they stay wound outward.
///
/// Primitives: a box is its 12-triangle mesh (exact); a cylinder is the prism over a
/// regular kCylinderSlices-gon inscribed in it (make_cylinder: inside the cylinder, at
/// most radius (1 - cos(pi / kCylinderSlices)) = 0.5% of the radius inside its side); a
/// capsule is the polyhedron make_capsule inscribes in it (kCylinderSlices around,
/// kCapsuleStacks latitude bands per cap: inside the capsule, its facets at most 1% of
/// the radius inside the caps); a sphere is not meshed but kept as the sphere itself.
/// Because these meshes lie inside the true shape, LinkSolidPart::surface_gap bounds how
/// far the true surface can be from the mesh: a set that covers the mesh's surface covers
/// the true surface once every radius grows by that much.

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "medspheres/mesh/mesh_io.h"
#include "medspheres/robot/urdf_robot.h"
#include "medspheres/sphere_set.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// Sides of the prism a URDF cylinder is meshed as (and of a capsule's rings).
inline constexpr int kCylinderSlices = 32;
/// Latitude bands of each hemispherical cap of a meshed capsule.
inline constexpr int kCapsuleStacks = 8;

/// One meshed geometry element.
struct LinkSolidPart {
  TriangleMesh mesh;                                         ///< in G, scale applied
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< X_LG
  std::string source;  ///< the mesh file as resolved, or "box 0.1 0.2 0.3", "cylinder r l",
                       ///< "capsule r l"
  std::string sha256;  ///< of the mesh file; empty for primitives
  /// Identifies the geometry in G: the file's sha256 and the scale, or the primitive and
  /// its sizes (to 17 digits). Two parts with the same key have the same mesh.
  std::string key;
  /// An upper bound, rounded up, on the distance from any point of the element's true
  /// surface to the mesh: 0 for mesh files and boxes; radius (1 - cos(pi / slices)) for a
  /// cylinder; for a capsule, radius minus the least distance from an end of its axis to
  /// a facet plane. Unaffected by X_LG (rigid).
  double surface_gap = 0.0;
};

struct LinkSolid {
  std::string link;
  std::vector<LinkSolidPart> parts;  ///< meshed elements, in the URDF's order
  std::vector<Sphere> spheres;       ///< sphere elements, exactly, in L
  bool empty() const noexcept { return parts.empty() && spheres.empty(); }
  /// Every part placed at X_LG and concatenated, in L (vertex v of a part at X_LG v).
  /// The union of the parts is the solid its winding number defines. Empty mesh when the
  /// link has no meshed part.
  TriangleMesh placed_mesh() const;
  std::size_t triangles() const;
  /// The largest LinkSolidPart::surface_gap of the parts; 0 without parts.
  double surface_gap() const;
};

/// Loads every link's solid. Each mesh file is loaded once (load_mesh, one after the
/// other, in the calling thread) however many links use it.
/// \throws InputError (source: the URDF) naming the link and the problem: a mesh file that
///   cannot be loaded (the loader's message is kept).
std::vector<LinkSolid> load_link_solids(const UrdfRobot& robot,
                                        const MeshLoadOptions& options = {});

}  // namespace medspheres
