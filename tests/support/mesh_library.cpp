#include "support/mesh_library.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "medspheres/mesh/mesh_generators.h"
#include "support/mesh_writers.h"

namespace medspheres::test {

namespace {

int at_least(double v, int lo) {
  return std::max(lo, static_cast<int>(std::lround(v)));
}

// A mesh of kind \p kind with about \p target triangles (icospheres come in powers of 4).
TriangleMesh library_mesh(int kind, double target, std::mt19937_64& random) {
  std::uniform_real_distribution<double> size(0.5, 2.0);
  switch (kind) {
    case 0:
      return make_box({size(random), size(random), size(random)},
                      at_least(std::sqrt(target / 12.0), 1));
    case 1:
      return make_icosphere(size(random),
                            std::clamp(at_least(std::log(target / 20.0) / std::log(4.0), 1), 1, 4));
    case 2: {
      const double major = size(random) + 1.0;
      const int m = at_least(std::sqrt(target / 2.0), 3);
      return make_torus(major, major * 0.3, m, at_least(target / (2.0 * m), 3));
    }
    case 3: {
      const int slices = at_least(std::sqrt(target), 3);
      return make_capsule(size(random) * 0.5, size(random), slices,
                          at_least(target / (4.0 * slices), 1));
    }
    default:
      return make_cylinder(size(random) * 0.5, size(random), at_least(target / 4.0, 3));
  }
}

}  // namespace

std::vector<LibraryMesh> write_mesh_library(const std::string& dir, std::size_t count,
                                            std::uint64_t seed, std::size_t min_triangles,
                                            std::size_t max_triangles) {
  namespace fs = std::filesystem;
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> log_size(std::log(static_cast<double>(min_triangles)),
                                                  std::log(static_cast<double>(max_triangles)));
  std::vector<LibraryMesh> out;
  for (std::size_t i = 0; i < count; ++i) {
    const TriangleMesh mesh =
        library_mesh(static_cast<int>(i % 5), std::exp(log_size(random)), random);
    static const char* const kFolders[] = {"props", "props/small", "robots/arm", "scenes"};
    const char* const ext[] = {".off", ".stl", ".obj"};
    const std::string relative =
        std::string(kFolders[i % 4]) + "/mesh" + std::to_string(i) + ext[(i / 5) % 3];
    const fs::path path = fs::path(dir) / relative;
    fs::create_directories(path.parent_path());
    const std::string text = (i / 5) % 3 == 0   ? to_off(mesh)
                             : (i / 5) % 3 == 1 ? to_stl_binary(mesh)
                                                : to_obj(mesh);
    std::ofstream(path, std::ios::binary) << text;
    out.push_back({relative, mesh.triangles.size()});
  }
  return out;
}

}  // namespace medspheres::test
