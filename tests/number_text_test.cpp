// number_text.h: numbers and counted nouns as medspheres writes them for people.
#include <catch2/catch.hpp>

#include "medspheres/number_text.h"

using medspheres::count_text;
using medspheres::number_text;

TEST_CASE("count_text: the noun in the singular for one only", "[number_text]") {
  CHECK(count_text(1, "link") == "1 link");
  CHECK(count_text(0, "link") == "0 links");
  CHECK(count_text(2, "link") == "2 links");
  CHECK(count_text(11, "sphere") == "11 spheres");
  CHECK(count_text(1, "vertex", "vertices") == "1 vertex");
  CHECK(count_text(3, "vertex", "vertices") == "3 vertices");
  CHECK(count_text(18446744073709551615ull, "byte") == "18446744073709551615 bytes");
}

TEST_CASE("number_text: printf's %g in the C locale", "[number_text]") {
  CHECK(number_text(0.25) == "0.25");
  CHECK(number_text(1e-9) == "1e-09");
  CHECK(number_text(3.14159265, 3) == "3.14");
}
