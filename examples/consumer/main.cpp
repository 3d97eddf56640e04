// Loads a mesh, asks for a closest point, and round-trips a sphere set through a file,
// using only the installed medspheres headers and libraries.
#include <cstdio>
#include <exception>

#include <medspheres/io.h>
#include <medspheres/mesh_io.h>
#include <medspheres/mesh_query.h>
#include <medspheres/version.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer MESH OUT.spheres.json\n");
    return 2;
  }
  try {
    const medspheres::LoadedMesh loaded = medspheres::load_mesh(argv[1]);
    const medspheres::MeshQuery query(loaded.mesh);
    const Eigen::Vector3d centre = loaded.mesh.bounds().center();
    const medspheres::ClosestPoint cp = query.closest_point(centre);

    medspheres::SphereSet set;
    set.spheres.push_back({centre, cp.distance()});
    medspheres::save_sphere_set(set, argv[2]);
    const medspheres::SphereSet back = medspheres::load_sphere_set(argv[2]);
    std::printf("medspheres %s: %zu triangles, distance from the box centre %.6g, %zu sphere(s)\n",
                MEDSPHERES_VERSION_STRING, loaded.mesh.triangles.size(), cp.distance(),
                back.size());
    return back.size() == 1 && back.spheres[0].radius == cp.distance() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
