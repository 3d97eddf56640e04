// The spherized URDF reader (formats/spherized_urdf.h), with the per-link format oracle;
// the writer spherizes the fuzzed URDF itself with the spheres read from it.
#include "fuzz_robot_spheres.h"
#include "medspheres/formats/spherized_urdf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres::formats;
  const std::string text = medspheres::fuzz::text_of(data, size);
  medspheres::fuzz::check_robot_spheres_reader(
      text, parse_urdf_spheres,
      [&](const RobotSpheres& s) { return spherize_urdf(text, s, "fuzz.urdf"); });
  return 0;
}
