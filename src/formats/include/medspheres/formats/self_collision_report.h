#pragma once
/// \file
/// The self-collision report of a robot's output folder (self_collision.txt): how the
/// matrix was computed, the tool frames and default configuration and where they came
/// from, the count of pairs per class, and every pair with its class and whether a planner
/// skips it. Plain text for people; the robot file holds the same data for programs.

#include <cstddef>
#include <map>
#include <string>

#include "medspheres/formats/robot_spheres.h"
#include "medspheres/planner_setup.h"
#include "medspheres/robot_model.h"

namespace medspheres::formats {

/// Pairs per class of \p m: class -> (pairs, of them skipped).
std::map<PairClass, std::pair<std::size_t, std::size_t>> pair_class_counts(
    const SelfCollisionMatrix& m);

/// The report of \p model's planner setup (the default one when it has none), over the
/// links of \p spheres.
std::string self_collision_report(const RobotModel& model, const RobotSpheres& spheres);

}  // namespace medspheres::formats
