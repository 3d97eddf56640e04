// Loads a baked sphere set and asks FCL for the distance between two copies of it, as
// robotics code does at run time.
#include <cstdio>
#include <exception>
#include <memory>

#include <medspheres/fcl/sphere_set_geometry.h>
#include <medspheres/io.h>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fcl_example SPHERES.json\n");
    return 2;
  }
  try {
    const medspheres::SphereSet s = medspheres::load_sphere_set(argv[1]);
    auto g = std::make_shared<medspheres::fcl::SphereSetGeometry>(s);
    const double size = s.bounds().sizes().maxCoeff();
    fcl::Transform3d X_WA = fcl::Transform3d::Identity(), X_WB = fcl::Transform3d::Identity();
    X_WB.translation() = fcl::Vector3d(2.0 * size, 0.0, 0.0);
    fcl::CollisionObjectd a(g, X_WA), b(g, X_WB);
    fcl::DistanceRequestd req;
    req.enable_nearest_points = true;
    fcl::DistanceResultd res;
    const double d = medspheres::fcl::distance(&a, &b, req, res);
    std::printf("distance between two copies %.6g apart: %.6g\n", 2.0 * size, d);
    return d > 0.0 && d < 2.0 * size ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fcl_example: %s\n", e.what());
    return 1;
  }
}
