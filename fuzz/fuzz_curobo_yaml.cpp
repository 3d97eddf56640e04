// The cuRobo YAML reader (formats/curobo_yaml.h), with the per-link format oracle.
#include "fuzz_robot_spheres.h"
#include "medspheres/formats/curobo_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres::formats;
  medspheres::fuzz::check_robot_spheres_reader(
      medspheres::fuzz::text_of(data, size), parse_curobo_yaml,
      [](const RobotSpheres& s) { return curobo_yaml_text(s); });
  return 0;
}
