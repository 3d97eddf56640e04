// foam's JSON readers (formats/foam_json.h): the robot database, with the per-link format
// oracle, and the one-mesh list of levels, whose every level writes back to a fixed point.
#include "fuzz_robot_spheres.h"
#include "medspheres/formats/foam_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres;
  using namespace medspheres::formats;
  const std::string text = fuzz::text_of(data, size);
  if (is_foam_robot_json(text)) {
    fuzz::check_robot_spheres_reader(text, parse_foam_robot_json,
                                     [](const RobotSpheres& s) { return foam_robot_json(s); });
    return 0;
  }
  std::vector<FoamLevel> levels;
  if (!fuzz::accepts([&] { levels = parse_foam_mesh_json(text, "fuzz.json"); })) return 0;
  for (const FoamLevel& level : levels) {
    std::string once;
    if (!fuzz::accepts([&] { once = foam_mesh_json(level.spheres); })) continue;
    const std::vector<FoamLevel> back = parse_foam_mesh_json(once, "written.json");
    MEDSPHERES_FUZZ_CHECK(back.size() == 1);
    MEDSPHERES_FUZZ_CHECK(foam_mesh_json(back[0].spheres) == once);
  }
  return 0;
}
