// The SRDF readers: the spheres sidecar (formats/srdf_spheres.h), with the per-link format
// oracle, and the disabled collision pairs (formats/srdf_disabled_collisions.h).
#include "fuzz_robot_spheres.h"
#include "medspheres/formats/srdf_disabled_collisions.h"
#include "medspheres/formats/srdf_spheres.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres::formats;
  const std::string text = medspheres::fuzz::text_of(data, size);
  medspheres::fuzz::check_robot_spheres_reader(
      text, parse_srdf_spheres, [](const RobotSpheres& s) { return srdf_spheres_text(s, "fuzz"); });
  medspheres::fuzz::accepts([&] { parse_srdf_disabled_collisions(text, "fuzz.srdf"); });
  return 0;
}
