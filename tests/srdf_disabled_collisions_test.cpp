// The SRDF <disable_collisions> reader against hand-written documents.
#include <string>

#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/formats/srdf_disabled_collisions.h"

using namespace medspheres;
using namespace medspheres::formats;

TEST_CASE("SRDF disable_collisions pairs are read in order", "[formats][srdf]") {
  const std::string text = R"(<?xml version="1.0"?>
<robot name="arm">
  <group name="all"><chain base_link="base" tip_link="tool"/></group>
  <disable_collisions link1="base" link2="l1" reason="Adjacent"/>
  <link_sphere_approximation link="l1"><sphere center="0 0 0" radius="0.1"/></link_sphere_approximation>
  <disable_collisions link1="l2 &amp; co" link2="l3"/>
</robot>)";
  const auto pairs = parse_srdf_disabled_collisions(text, "arm.srdf");
  REQUIRE(pairs.size() == 2);
  CHECK(pairs[0].link1 == "base");
  CHECK(pairs[0].link2 == "l1");
  CHECK(pairs[0].reason == "Adjacent");
  CHECK(pairs[1].link1 == "l2 & co");
  CHECK(pairs[1].link2 == "l3");
  CHECK(pairs[1].reason.empty());
}

TEST_CASE("SRDF disable_collisions errors name the file", "[formats][srdf]") {
  for (const std::string& bad :
       {std::string("<robot><disable_collisions link1=\"a\"/></robot>"),
        std::string("<robot><disable_collisions link1=\"\" link2=\"b\"/></robot>"),
        std::string("<not_robot/>"), std::string("<robot>")}) {
    INFO(bad);
    try {
      parse_srdf_disabled_collisions(bad, "bad.srdf");
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find("bad.srdf") != std::string::npos);
    }
  }
}
