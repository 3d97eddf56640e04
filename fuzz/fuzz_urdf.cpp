// Robot reading from a URDF (robot/urdf_robot.h through urdfdom) into link solids
// (robot/link_solid.h). Mesh elements are parsed and resolved but not loaded: the
// fuzzer drops them before load_link_solids (mesh files are assimp's, fuzzed apart from
// this), so that the primitives (box, cylinder, sphere) are meshed and placed.
// Oracles: the model an accepted URDF gives is valid, and every solid is in the model's
// link order with finite coordinates and in-range indices.
#include <algorithm>

#include "fuzz_support.h"
#include "medspheres/robot/link_solid.h"
#include "medspheres/robot/urdf_robot.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace medspheres;
  UrdfReadOptions options;
  options.packages.use_ros_package_path = false;
  options.from_visual = size > 0 && (data[size - 1] & 1) != 0;
  UrdfRobot robot;
  if (!fuzz::accepts([&] {
        robot =
            parse_urdf(fuzz::text_of(data, size), "fuzz.urdf", "/nonexistent-fuzz-dir", options);
      }))
    return 0;
  validate_robot_model(robot.model, "accepted urdf");
  MEDSPHERES_FUZZ_CHECK(robot.links.size() == robot.model.links.size());
  for (UrdfLink& link : robot.links)
    link.parts.erase(std::remove_if(link.parts.begin(), link.parts.end(),
                                    [](const LinkPart& p) { return p.shape == PartShape::kMesh; }),
                     link.parts.end());
  const std::vector<LinkSolid> solids = load_link_solids(robot);
  MEDSPHERES_FUZZ_CHECK(solids.size() == robot.links.size());
  for (std::size_t i = 0; i < solids.size(); ++i) {
    MEDSPHERES_FUZZ_CHECK(solids[i].link == robot.links[i].name);
    const TriangleMesh mesh = solids[i].placed_mesh();
    for (const Eigen::Vector3d& v : mesh.vertices) MEDSPHERES_FUZZ_CHECK(v.allFinite());
    for (const auto& t : mesh.triangles)
      for (const int k : t)
        MEDSPHERES_FUZZ_CHECK(k >= 0 && static_cast<std::size_t>(k) < mesh.vertices.size());
  }
  return 0;
}
