#pragma once
// The oracle shared by the fuzz targets of the per-link sphere formats: a reader's
// accepted input is valid (validate_robot_spheres), and when the format's writer takes it,
// writing after reading is a fixed point.
#include <string>

#include "fuzz_support.h"
#include "medspheres/formats/robot_spheres.h"

namespace medspheres::fuzz {

template <class Read, class Write>
void check_robot_spheres_reader(const std::string& text, Read read, Write write) {
  formats::RobotSpheres spheres;
  if (!accepts([&] { spheres = read(text, std::string("fuzz")); })) return;
  formats::validate_robot_spheres(spheres, "accepted input");
  std::string once;
  if (!accepts([&] { once = write(spheres); })) return;
  const std::string twice = write(read(once, std::string("written")));
  MEDSPHERES_FUZZ_CHECK(once == twice);
}

}  // namespace medspheres::fuzz
