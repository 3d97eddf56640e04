#pragma once
// The checks of the abs_err / rel_err tests (FCL's DistanceRequest tolerances), shared by
// the sphere-set pair tests and the target tests. Header-only; needs Catch2.

#include <algorithm>
#include <cstddef>
#include <vector>

#include <catch2/catch.hpp>

#include "support/fcl_fixtures.h"

namespace medspheres::test {

/// Checks an answer d, obtained under `mode` with the request's `abs_err`, against the
/// exact minimum `exact` (d*): d* <= d <= min(d* + abs_err, (1 + rel_err) d*), and d == d*
/// unless the mode is loose, all within `tol`. Returns whether d exceeds d* + tol.
inline bool check_within_tolerance(const ToleranceMode& mode, double abs_err, double exact,
                                   double d, double tol) {
  CHECK(d >= exact - tol);
  CHECK(d <= std::min(exact + abs_err, (1 + mode.rel_err) * exact) + tol);
  if (!mode.loose) CHECK(d == Approx(exact).margin(tol));
  return d > exact + tol;
}

/// `inexact[m]` counts the answers of kToleranceModes[m] above d* over `scenes` scenes:
/// checks that exactly the loose modes have some (only they prune).
inline void check_only_loose_modes_prune(const std::vector<int>& inexact, int scenes) {
  for (std::size_t m = 0; m < kToleranceModes.size(); ++m) {
    INFO(kToleranceModes[m].name << ": " << inexact[m] << " inexact answers over " << scenes);
    CHECK((inexact[m] > 0) == kToleranceModes[m].loose);
  }
}

}  // namespace medspheres::test
