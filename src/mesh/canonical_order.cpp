#include "medspheres/mesh/canonical_order.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>
#include <vector>

namespace medspheres {

namespace {

// x < y in (x, y, z) order, with -0.0 before +0.0 so that the order is total on the
// non-NaN doubles the loader keeps apart.
bool position_less(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  for (int i = 0; i < 3; ++i) {
    if (a[i] != b[i]) return a[i] < b[i];
    const bool na = std::signbit(a[i]), nb = std::signbit(b[i]);
    if (na != nb) return na;
  }
  return false;
}

}  // namespace

void canonicalize_order(TriangleMesh& mesh) {
  const std::size_t nv = mesh.vertices.size();
  std::vector<int> order(nv);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return position_less(mesh.vertices[static_cast<std::size_t>(a)],
                         mesh.vertices[static_cast<std::size_t>(b)]);
  });
  std::vector<int> rank(nv);
  std::vector<Eigen::Vector3d> sorted(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    rank[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
    sorted[i] = mesh.vertices[static_cast<std::size_t>(order[i])];
  }
  mesh.vertices = std::move(sorted);
  for (auto& t : mesh.triangles) {
    for (int& v : t) v = rank[static_cast<std::size_t>(v)];
    const auto first = std::min_element(t.begin(), t.end());
    std::rotate(t.begin(), first, t.end());  // a cyclic shift keeps the winding
  }
  std::sort(mesh.triangles.begin(), mesh.triangles.end());
}

}  // namespace medspheres
