#pragma once
/// \file
/// Closed, outward-oriented triangle meshes of simple solids whose ideal shape (medial
/// surface, volume, distance field) is known. Every mesh is watertight (each edge shared
/// by exactly two triangles, vertices shared), wound counter-clockwise seen from outside,
/// and inscribed in the ideal solid (vertices on its surface).

#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// Axis-aligned box [-h, h] (componentwise), each face split into n x n squares.
/// \throws std::invalid_argument unless every h > 0 and n >= 1.
TriangleMesh make_box(const Eigen::Vector3d& half_extents, int n = 1);

/// Sphere of the given radius about the origin: an icosahedron subdivided
/// \p subdivisions times (20 * 4^subdivisions triangles).
/// \throws std::invalid_argument unless radius > 0 and 0 <= subdivisions <= 8.
TriangleMesh make_icosphere(double radius, int subdivisions);

/// Torus about the z axis: tube of radius \p minor around a circle of radius \p major
/// in the xy plane; 2 * major_segments * minor_segments triangles.
/// \throws std::invalid_argument unless 0 < minor < major and both segment counts >= 3.
TriangleMesh make_torus(double major, double minor, int major_segments, int minor_segments);

/// Capsule along z: the set of points within \p radius of the segment from
/// (0, 0, -half_length) to (0, 0, half_length). \p slices around the axis and
/// \p stacks latitude bands per hemispherical cap.
/// \throws std::invalid_argument unless radius > 0, half_length >= 0, slices >= 3, stacks >= 1.
TriangleMesh make_capsule(double radius, double half_length, int slices, int stacks);

/// Cylinder along z: the prism over a regular \p slices-gon inscribed in the circle of
/// \p radius, from z = -half_length to half_length (4 * slices triangles; the disc caps
/// are fans from their centres). It lies inside the ideal cylinder; its side is at most
/// radius (1 - cos(pi / slices)) inside it.
/// \throws std::invalid_argument unless radius > 0, half_length > 0, slices >= 3.
TriangleMesh make_cylinder(double radius, double half_length, int slices);

}  // namespace medspheres
