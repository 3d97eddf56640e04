// The cover's surface elements (src/cover/cover_elements.h): their size against the budget.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <catch2/catch.hpp>

#include "../src/cover/cover_elements.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_query.h"

using namespace medspheres;

TEST_CASE("cover elements: a larger budget above K = 64 never gets coarser elements", "[cover]") {
  // A torus of 38,400 triangles: from K = 512 on, the size L / (2 + 3 sqrt K) would make
  // more elements than the cap (twice the triangles), so the size is coarsened until they
  // fit. Coarsened by 1.5 at a time from each K's own start, K = 1024 landed on coarser
  // elements than K = 512. Oracles: the sizes never grow with K, the count stays within the
  // cap, and a size a hair finer than a coarsened one exceeds it (each triangle subdivided
  // as the bake does): the finest size that fits.
  const TriangleMesh torus = make_torus(1.0, 0.3, 240, 80);
  const MeshQuery query(torus);
  const double cap = 2.0 * static_cast<double>(torus.num_triangles());
  const double L = torus.bounds().sizes().maxCoeff();
  double previous = 0.0;
  for (const std::size_t k : std::vector<std::size_t>{128, 256, 512, 1024, 2048, 4096, 16384}) {
    INFO("K = " << k);
    const detail::Elements e = detail::make_elements(query, k, 0, 1);
    CHECK(static_cast<double>(e.surface) <= cap);
    if (previous > 0.0) CHECK(e.element_size <= previous);
    previous = e.element_size;
    if (e.element_size <= L / (2.0 + 3.0 * std::sqrt(static_cast<double>(k)))) continue;
    double finer = 0.0;
    for (std::size_t t = 0; t < torus.num_triangles(); ++t) {
      const Eigen::Vector3d &a = torus.corner(t, 0), &b = torus.corner(t, 1),
                            &c = torus.corner(t, 2);
      const double edge = std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()});
      int d = 0;
      while (d < detail::kMaxElementDepth && edge > e.element_size * (1.0 - 1e-9) * (1 << d)) ++d;
      finer += static_cast<double>(1 << (2 * d));
    }
    CHECK(finer > cap);
  }
}
