#pragma once
// The order of the kernel's tests (each link against the scene, each self pair: index
// k < links is link k's, the others pair k - links; the bounds mode runs them in this
// order within each level). A configuration collides when any test finds it colliding, so
// every order gives the same verdicts; the order only decides how soon a colliding
// configuration stops. RobotChecker learns one at
// construction (CheckerOptions::order_samples): the tests that found collisions most
// often in configurations drawn within the joints' limits first.

#include <cstdint>
#include <vector>

namespace medspheres::check::detail {

/// The tests ordered by \p hits (per test: the configurations it found colliding), most
/// first; ties keep the tests' own order.
std::vector<std::uint32_t> order_by_hits(const std::vector<std::uint32_t>& hits);

}  // namespace medspheres::check::detail
