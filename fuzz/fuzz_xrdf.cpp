// The XRDF reader (formats/xrdf.h), with the per-link format oracle.
#include "fuzz_robot_spheres.h"
#include "medspheres/formats/xrdf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres::formats;
  medspheres::fuzz::check_robot_spheres_reader(medspheres::fuzz::text_of(data, size), parse_xrdf,
                                               [](const RobotSpheres& s) { return xrdf_text(s); });
  return 0;
}
