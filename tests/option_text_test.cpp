// The options layer (medspheres/options/): option text read into typed values.
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/options/option_text.h"

using namespace medspheres;

TEST_CASE("parse_length reads absolute and relative lengths", "[options]") {
  CHECK(parse_length("0.25").value == 0.25);
  CHECK_FALSE(parse_length("0.25").relative);
  CHECK(parse_length("0.003L").relative);
  CHECK(parse_length("0.003l").value == 0.003);
  CHECK(parse_length("0.5L").in(4.0) == 2.0);
  CHECK(parse_length("0.5").in(4.0) == 0.5);
  for (const std::string bad : {"", "L", "abc", "0.1LL", "1e", "0.1 L"}) {
    INFO(bad);
    try {
      parse_length(bad);
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(e.kind() == ErrorKind::kOutOfRange);
      CHECK(e.field() == "length");
      CHECK(e.value() == bad);
      CHECK_THAT(e.what(), Catch::Matchers::Contains("'" + bad + "'"));
    }
  }
}

TEST_CASE("parse_solid_kind reads the names to_string writes", "[options]") {
  for (SolidKind k : {SolidKind::kAuto, SolidKind::kWinding, SolidKind::kRobust})
    CHECK(parse_solid_kind(to_string(k)) == k);
  CHECK(parse_solid_kind("robust") == SolidKind::kRobust);
  try {
    parse_solid_kind("voxel");
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.kind() == ErrorKind::kOutOfRange);
    CHECK(e.field() == "solid");
    CHECK(e.value() == "voxel");
  }
}
