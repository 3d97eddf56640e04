// Every library component above the mesh, from an installed medspheres: option text read
// into a request (options), a bake to a budget (bake), its exact fit (measure), a certified
// cover (cover), the inputs of a batch (batch) and a robot's default budget (robot_bake).
#include <cstdio>
#include <exception>

#include <medspheres/bake/bake_pipeline.h>
#include <medspheres/batch/batch_inputs.h>
#include <medspheres/cover/cover.h>
#include <medspheres/measure/fit_metrics.h>
#include <medspheres/mesh/mesh_io.h>
#include <medspheres/mesh/mesh_query.h>
#include <medspheres/options/bake_flags.h>
#include <medspheres/robot_bake/robot_bake.h>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: library_example MESH\n");
    return 2;
  }
  try {
    medspheres::BakeFlags flags;
    flags.max_spheres = 16;
    flags.solid.solid = "winding";
    const medspheres::BakeRequest request = medspheres::bake_request(flags);
    const medspheres::BakeOutcome baked = medspheres::bake_file(argv[1], request);
    const medspheres::LoadedMesh loaded = medspheres::load_mesh(argv[1]);
    const medspheres::VolumeError fit =
        medspheres::FitEvaluator(loaded.mesh).volume_error(baked.spheres.spheres);
    const medspheres::CoverResult cover =
        medspheres::bake_cover(medspheres::MeshQuery(loaded.mesh), 4);
    const std::size_t inputs = medspheres::collect_inputs({argv[1]}).size();
    std::printf("%zu spheres, nerr %.4f; cover of %zu %s; %zu batch input; %zu per link\n",
                baked.spheres.size(), fit.nerr, cover.spheres.size(),
                cover.certificate.certified ? "certified" : "NOT certified", inputs,
                medspheres::kDefaultSpheresPerLink);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "library_example: %s\n", e.what());
    return 1;
  }
}
