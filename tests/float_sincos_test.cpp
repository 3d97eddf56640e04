// float_sincos_reduced (src/check/float_sincos.h), the float pass's sine and cosine,
// against sin and cos in long double: within kFloatSinCosError of them for every float r
// of [0.76, 0.7854] and a stride through [0, 0.76], on both sides, with the double angle
// r_d it was rounded from half an ulp away on either side (the rounding the bound
// charges). The float slack (robot_checker.cpp) is derived from this bound: a bound cut
// below the error measured here fails.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <catch2/catch.hpp>

#include "../src/check/float_sincos.h"

using medspheres::check::detail::float_sincos_reduced;
using medspheres::check::detail::kFloatSinCosError;

namespace {

// The largest error of the float sine and cosine of r against r_d = r and r -+ half an
// ulp of r.
double worst_at(float r) {
  float s = 0.0f, c = 0.0f;
  float_sincos_reduced(r, s, c, [](float x) { return x; });
  const double half_ulp = (double(std::nextafter(r, 2.0f)) - double(r)) / 2;
  double worst = 0.0;
  for (const double d : {0.0, -half_ulp, half_ulp}) {
    const long double rd = static_cast<long double>(double(r) + d);
    worst = std::max(worst, double(std::fabs(static_cast<long double>(s) - std::sin(rd))));
    worst = std::max(worst, double(std::fabs(static_cast<long double>(c) - std::cos(rd))));
  }
  return worst;
}

}  // namespace

TEST_CASE("float sine and cosine: within kFloatSinCosError of the double angle's", "[check]") {
  const double u = std::ldexp(1.0, -24);
  double worst = 0.0;
  std::size_t tested = 0;
  for (const float sign : {1.0f, -1.0f}) {
    // Every float of [0.76, 0.7854], where the values and their roundings are largest.
    for (float r = 0.76f; r <= 0.7854f; r = std::nextafter(r, 1.0f), ++tested)
      worst = std::max(worst, worst_at(sign * r));
    // Then a stride through [0, 0.76].
    for (std::uint32_t k = 0; k < 100000; ++k, ++tested)
      worst = std::max(worst, worst_at(sign * 0.76f * float(k) / 100000.0f));
  }
  INFO("largest error " << worst / u << " u over " << tested << " angles; bound "
                        << kFloatSinCosError / u << " u");
  CHECK(tested > 1000000);
  CHECK(worst <= kFloatSinCosError);
  // The measured error is of the bound's order: a sweep that never came near it would not
  // test it.
  CHECK(worst > kFloatSinCosError / 4);
}
