#pragma once
/// \file
/// The smallest ball that encloses a set of balls (a point is a ball of radius 0).
///
/// min_enclosing_ball(balls) returns a ball that contains every input ball and whose
/// radius is at most (1 + kEnclosingBallSlack) times the smallest possible one, to
/// rounding: cutting planes over Welzl's algorithm for points (derivation in
/// min_enclosing_ball.cpp). The returned radius is recomputed from the returned centre to
/// enclose every input ball and rounded up by 16 eps (|c|_inf + r), so containment holds
/// in floating point. Frame and units: those of the input. Deterministic: the same input
/// in the same order gives the same bits.

#include <vector>

#include "medspheres/sphere_set.h"

namespace medspheres {

/// The relative tolerance of min_enclosing_ball's radius over the minimum's.
inline constexpr double kEnclosingBallSlack = 1e-9;

/// The smallest ball holding every ball of \p balls, within kEnclosingBallSlack (file
/// comment). One ball is returned as it is.
/// \throws std::invalid_argument for an empty set, or a ball with a non-finite centre or a
///   radius that is negative or not finite (the message names its index).
Sphere min_enclosing_ball(const std::vector<Sphere>& balls);

}  // namespace medspheres
