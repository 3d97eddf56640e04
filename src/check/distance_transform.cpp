#include "distance_transform.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace medspheres::check::detail {
namespace {

// One line: d[q] = min_p (q - p)^2 + f[p], by the lower envelope of the parabolas rooted
// at every p (the paper's algorithm DT, exact for integer spacing).
void transform_line(const double* f, int n, double* d, std::vector<int>& v,
                    std::vector<double>& z) {
  const double inf = std::numeric_limits<double>::infinity();
  int k = 0;
  v[0] = 0;
  z[0] = -inf;
  z[1] = inf;
  auto meet = [&](int q, int p) {  // where the parabolas rooted at q and p cross
    return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * q - 2.0 * p);
  };
  for (int q = 1; q < n; ++q) {
    // z[0] = -inf stops the loop at k = 0 at the latest.
    double s = meet(q, v[static_cast<std::size_t>(k)]);
    while (s <= z[static_cast<std::size_t>(k)]) s = meet(q, v[static_cast<std::size_t>(--k)]);
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k) + 1] = inf;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[static_cast<std::size_t>(k) + 1] < q) ++k;
    const int p = v[static_cast<std::size_t>(k)];
    d[q] = double(q - p) * (q - p) + f[p];
  }
}

}  // namespace

std::vector<double> squared_distance_transform(const std::vector<char>& marked, int nx, int ny,
                                               int nz) {
  const double far = 3.0 * double(nx + ny + nz) * double(nx + ny + nz);
  std::vector<double> g(marked.size());
  for (std::size_t i = 0; i < marked.size(); ++i) g[i] = marked[i] ? 0.0 : far;
  const int longest = nx > ny ? (nx > nz ? nx : nz) : (ny > nz ? ny : nz);
  std::vector<double> line(static_cast<std::size_t>(longest)), out(line.size());
  std::vector<int> v(line.size());
  std::vector<double> z(line.size() + 1);
  const long sx = 1, sy = nx, sz = long(nx) * ny;
  const int dims[3] = {nx, ny, nz};
  const long strides[3] = {sx, sy, sz};
  for (int axis = 0; axis < 3; ++axis) {
    const int n = dims[axis];
    const long stride = strides[axis];
    const int a = axis == 0 ? ny : nx, b = axis == 2 ? ny : nz;
    const long sa = axis == 0 ? sy : sx, sb = axis == 2 ? sy : sz;
    for (int j = 0; j < b; ++j)
      for (int i = 0; i < a; ++i) {
        const long base = i * sa + j * sb;
        for (int q = 0; q < n; ++q)
          line[static_cast<std::size_t>(q)] = g[static_cast<std::size_t>(base + q * stride)];
        transform_line(line.data(), n, out.data(), v, z);
        for (int q = 0; q < n; ++q)
          g[static_cast<std::size_t>(base + q * stride)] = out[static_cast<std::size_t>(q)];
      }
  }
  return g;
}

std::vector<double> boxes_distance_transform(const std::vector<Element>& elements,
                                             const double* origin, double h, const int* n,
                                             double pad) {
  std::vector<char> touched(std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]), 0);
  for (const Element& e : elements) {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::max(0, int(std::floor((e.box.min()[k] - pad - origin[k]) / h)));
      hi[k] = std::min(n[k] - 1, int(std::floor((e.box.max()[k] + pad - origin[k]) / h)));
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x)
          touched[std::size_t(x) + n[0] * (std::size_t(y) + std::size_t(n[1]) * z)] = 1;
  }
  return squared_distance_transform(touched, n[0], n[1], n[2]);
}

}  // namespace medspheres::check::detail
