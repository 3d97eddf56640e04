#pragma once
// A robot's left-right mirror image by its links' names, checked against its tree: the
// self-collision matrix checks a pair whose mirror image it saw colliding
// (self_collision_matrix.h).

#include <optional>
#include <string>
#include <vector>

#include "medspheres/robot_model.h"

namespace medspheres {

/// \p name with its side swapped: every "left" and "right" (lower, Capitalised or UPPER case)
/// exchanged; else every "l_"/"r_" at its start, "_l"/"_r" at its end and "_l_"/"_r_" within
/// (either case); nullopt when it names no side.
std::optional<std::string> swap_side(const std::string& name);

/// Per link of \p model, its mirror image's index (itself when its name names no side), or
/// empty when the tree is not its own mirror image: a sided link's swapped name is no link,
/// or a joint's image (the joint of the image of its child) has another parent or type, or an
/// offset length or range of motion more than 0.001 (metres, radians) from its own.
std::vector<std::size_t> mirror_links(const RobotModel& model);

}  // namespace medspheres
