// Bakes medial spheres of a mesh and writes them to a sphere-set file, using only the
// installed medspheres headers and libraries.
#include <cstdio>
#include <exception>

#include <medspheres/bake/bake.h>
#include <medspheres/io.h>
#include <medspheres/mesh/mesh_io.h>
#include <medspheres/version.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: bake_example MESH OUT.spheres.json\n");
    return 2;
  }
  try {
    const medspheres::LoadedMesh loaded = medspheres::load_mesh(argv[1]);
    const medspheres::BakeResult result = medspheres::bake(loaded.mesh);
    medspheres::save_sphere_set(result.spheres, argv[2]);
    std::printf("medspheres %s: %zu triangles, %zu spheres\n", MEDSPHERES_VERSION_STRING,
                loaded.mesh.triangles.size(), result.spheres.size());
    return result.spheres.empty() ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bake_example: %s\n", e.what());
    return 1;
  }
}
