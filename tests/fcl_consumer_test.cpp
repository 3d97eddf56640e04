// The consumer code of docs/certified-queries.md ("Using a baked sphere set in FCL") inside
// a test: these names must compile and work.

#include <filesystem>

#include <medspheres/fcl/sphere_set_geometry.h>
#include <medspheres/io.h>
#include <catch2/catch.hpp>

#include "support/temp_dir.h"

TEST_CASE("The documented consumer code compiles and runs", "[fcl]") {
  // The snippet reads "link.spheres.json" from the working directory.
  const medspheres::test::TempDir dir;
  medspheres::SphereSet written;
  written.spheres.push_back({Eigen::Vector3d(0, 0, 0), 0.5});
  written.spheres.push_back({Eigen::Vector3d(1, 0, 0), 0.25});
  medspheres::save_sphere_set(written, dir.file("link.spheres.json"));
  const std::filesystem::path previous = std::filesystem::current_path();
  std::filesystem::current_path(dir.path());
  fcl::Transform3d X_WA = fcl::Transform3d::Identity(), X_WB = fcl::Transform3d::Identity();
  X_WB.translation() = Eigen::Vector3d(0, 3, 0);

  // clang-format off
  medspheres::SphereSet s = medspheres::load_sphere_set("link.spheres.json");
  auto g = std::make_shared<medspheres::fcl::SphereSetGeometry>(s);
  fcl::CollisionObjectd a(g, X_WA), b(g, X_WB);
  fcl::DistanceRequestd req; req.enable_nearest_points = true; fcl::DistanceResultd res;
  double d = medspheres::fcl::distance(&a, &b, req, res);
  // clang-format on

  std::filesystem::current_path(previous);
  CHECK(d == 2.0);
  CHECK(res.nearest_points[0] == Eigen::Vector3d(0, 0.5, 0));
  CHECK(res.nearest_points[1] == Eigen::Vector3d(0, 2.5, 0));
}
