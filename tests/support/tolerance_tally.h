#pragma once
// The checks of FCL's abs_err / rel_err guarantee shared by the adapter tests: each
// tolerant answer against the exact minimum, and, over the scenes, that exactly the
// loose modes (both tolerances binding) ever prune. Header-only.

#include <algorithm>
#include <cstddef>
#include <vector>

#include <catch2/catch.hpp>

#include "support/fcl_fixtures.h"

namespace medspheres::test {

class ToleranceTally {
 public:
  ToleranceTally() : inexact_(kToleranceModes.size(), 0) {}

  /// Counts one scene whose exact minimum is apart.
  void add_scene() { ++scenes_; }

  /// Checks answer d of mode m against the exact minimum: exact - tol <= d <=
  /// min(exact + abs_err, (1 + rel_err) exact) + tol, and d == exact unless the mode is
  /// loose. \p counted: whether an inexact answer counts towards the mode's tally.
  void check(std::size_t m, double d, double exact, double abs_err, double tol, bool counted) {
    const ToleranceMode& mode = kToleranceModes[m];
    CHECK(d >= exact - tol);
    CHECK(d <= std::min(exact + abs_err, (1 + mode.rel_err) * exact) + tol);
    if (!mode.loose) CHECK(d == Approx(exact).margin(tol));
    if (counted && d > exact + tol) ++inexact_[m];
  }

  /// At least \p min_scenes scenes, and inexact answers in exactly the loose modes.
  void check_totals(int min_scenes) const {
    CHECK(scenes_ >= min_scenes);
    for (std::size_t m = 0; m < kToleranceModes.size(); ++m) {
      INFO(kToleranceModes[m].name << ": " << inexact_[m] << " inexact answers over " << scenes_);
      CHECK((inexact_[m] > 0) == kToleranceModes[m].loose);  // only loose modes prune
    }
  }

 private:
  std::vector<int> inexact_;
  int scenes_ = 0;
};

}  // namespace medspheres::test
