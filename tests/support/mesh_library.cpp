#include "support/mesh_library.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>

#include "medspheres/mesh/mesh_generators.h"
#include "support/mesh_writers.h"

namespace medspheres::test {

namespace {

int at_least(double v, int lo) {
  return std::max(lo, static_cast<int>(std::lround(v)));
}

// The icosphere subdivision (20 * 4^k triangles) within [lo, hi] nearest to \p target on a
// log scale.
int icosphere_level(double target, std::size_t lo, std::size_t hi) {
  int best = -1;
  for (int k = 0; k <= 8; ++k) {
    const double n = 20.0 * std::pow(4.0, k);
    if (n < static_cast<double>(lo) || n > static_cast<double>(hi)) continue;
    if (best < 0 ||
        std::abs(std::log(n / target)) < std::abs(std::log(20.0 * std::pow(4.0, best) / target)))
      best = k;
  }
  if (best < 0) throw std::invalid_argument("write_mesh_library: no icosphere in the range");
  return best;
}

// A mesh of kind \p kind with about \p target triangles, of the sizes \p s (in [0.5, 2]).
TriangleMesh library_mesh(int kind, double target, const double (&s)[3]) {
  switch (kind) {
    case 0:
      return make_box({s[0], s[1], s[2]}, at_least(std::sqrt(target / 12.0), 1));
    case 2: {
      const double major = s[0] + 1.0;
      const int m = at_least(std::sqrt(target / 2.0), 3);
      return make_torus(major, major * 0.3, m, at_least(target / (2.0 * m), 3));
    }
    case 3: {
      const int slices = at_least(std::sqrt(target), 3);
      return make_capsule(s[0] * 0.5, s[1], slices, at_least(target / (4.0 * slices), 1));
    }
    default:
      return make_cylinder(s[0] * 0.5, s[1], at_least(target / 4.0, 3));
  }
}

// A mesh of kind \p kind with about \p target triangles and at least \p lo, at most \p hi:
// the parameters rounded from the target can miss the range (a box's 12 n^2), so the target
// is moved toward the range until the count lies in it.
TriangleMesh mesh_in_range(int kind, double target, std::size_t lo, std::size_t hi,
                           std::mt19937_64& random) {
  std::uniform_real_distribution<double> size(0.5, 2.0);
  const double s[3] = {size(random), size(random), size(random)};
  if (kind == 1) return make_icosphere(s[0], icosphere_level(target, lo, hi));
  for (int attempt = 0; attempt < 32; ++attempt) {
    TriangleMesh mesh = library_mesh(kind, target, s);
    const double n = static_cast<double>(mesh.triangles.size());
    if (n >= static_cast<double>(lo) && n <= static_cast<double>(hi)) return mesh;
    target *= n < static_cast<double>(lo) ? 1.1 * static_cast<double>(lo) / n
                                          : 0.9 * static_cast<double>(hi) / n;
  }
  throw std::invalid_argument("write_mesh_library: the triangle range is too narrow");
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
    const double target = std::exp(log_size(random));
    const TriangleMesh mesh =
        mesh_in_range(static_cast<int>(i % 5), target, min_triangles, max_triangles, random);
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
