#pragma once
/// \file
/// spheretree's .sph file (Bradshaw and O'Sullivan's sphere-tree construction toolkit):
/// the header "levels degree", then the nodes of a complete tree level by level (level l
/// holds degree^l lines), each "x y z r occupancy" and optionally five more numbers (an
/// auxiliary sphere and its error). Nodes with r <= 0 are unused.
///
/// medspheres writes a set of K spheres as spheretree's own saveSpheres does: "2 K", then
/// a root sphere that encloses them all (centroid of the centres, radius the largest
/// distance plus radius, enlarged by 1e-12 relative for rounding), then the K spheres with
/// occupancy 1. Numbers are written in their shortest exact form (spheretree itself reads
/// them into floats).

#include <string>
#include <vector>

#include "medspheres/sphere_set.h"

namespace medspheres::formats {

/// The .sph text. \throws InputError for an empty or invalid set.
std::string sph_text(const std::vector<Sphere>& spheres);

/// Every level's used nodes (r > 0), root level first.
/// \throws InputError naming \p source, the level, the node and the problem: a bad header,
///   a missing or malformed node line, an invalid sphere.
std::vector<std::vector<Sphere>> parse_sph_levels(const std::string& text,
                                                  const std::string& source);

}  // namespace medspheres::formats
