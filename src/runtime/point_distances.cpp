#include "medspheres/point_distances.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace medspheres {

void point_distances(const SphereTree& a, const Eigen::Isometry3d& X_WA, const double* xyz,
                     std::size_t n, double* out, std::intptr_t* sphere) {
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!p.allFinite())
      throw std::invalid_argument("point " + std::to_string(i) + " is not finite");
    const TreeDistance d = distance(a, X_WA, p);
    out[i] = d.distance;
    if (sphere) sphere[i] = d.sphere_a;
  }
}

}  // namespace medspheres
