#include "medspheres/mesh/mesh_generators.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

namespace medspheres {

namespace {

constexpr double kPi = 3.14159265358979323846;

int add_vertex(TriangleMesh& m, const Eigen::Vector3d& p) {
  m.vertices.push_back(p);
  return static_cast<int>(m.vertices.size() - 1);
}

// Quad a-b-c-d, counter-clockwise seen from outside, as two triangles.
void add_quad(TriangleMesh& m, int a, int b, int c, int d) {
  m.triangles.push_back({a, b, c});
  m.triangles.push_back({a, c, d});
}

}  // namespace

TriangleMesh make_box(const Eigen::Vector3d& h, int n) {
  if (!(h.minCoeff() > 0.0) || !h.allFinite())
    throw std::invalid_argument("make_box: half extents must be finite and > 0");
  if (n < 1) throw std::invalid_argument("make_box: n must be >= 1");
  TriangleMesh m;
  // Surface lattice points (i, j, k) in [0, n]^3 with at least one coordinate on the
  // boundary; a map shares the vertices along face edges.
  std::map<std::tuple<int, int, int>, int> index;
  auto vertex = [&](int i, int j, int k) {
    auto key = std::make_tuple(i, j, k);
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    Eigen::Vector3d p(-h.x() + 2.0 * h.x() * i / n, -h.y() + 2.0 * h.y() * j / n,
                      -h.z() + 2.0 * h.z() * k / n);
    const int id = add_vertex(m, p);
    index.emplace(key, id);
    return id;
  };
  // For each axis and side, walk the face grid with (u, v) so that u x v is outward.
  for (int axis = 0; axis < 3; ++axis) {
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;  // (ua, va, axis) right-handed
    for (int side = 0; side < 2; ++side) {
      for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
          auto at = [&](int u, int v) {
            int c[3];
            c[axis] = side == 1 ? n : 0;
            c[ua] = u;
            c[va] = v;
            return vertex(c[0], c[1], c[2]);
          };
          const int p00 = at(a, b), p10 = at(a + 1, b), p11 = at(a + 1, b + 1), p01 = at(a, b + 1);
          if (side == 1)
            add_quad(m, p00, p10, p11, p01);
          else
            add_quad(m, p00, p01, p11, p10);
        }
      }
    }
  }
  return m;
}

TriangleMesh make_icosphere(double radius, int subdivisions) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw std::invalid_argument("make_icosphere: radius must be finite and > 0");
  if (subdivisions < 0 || subdivisions > 8)
    throw std::invalid_argument("make_icosphere: subdivisions must be in [0, 8]");
  TriangleMesh m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const double base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                              {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                              {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (const auto& b : base) add_vertex(m, Eigen::Vector3d(b[0], b[1], b[2]).normalized());
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const Eigen::Vector3d p = (m.vertices[a] + m.vertices[b]).normalized();
      const int id = add_vertex(m, p);
      mid.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(m.triangles.size() * 4);
    for (const auto& tri : m.triangles) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]),
                c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles.swap(next);
  }
  for (auto& v : m.vertices) v *= radius;
  return m;
}

TriangleMesh make_torus(double major, double minor, int nu, int nv) {
  if (!(minor > 0.0) || !(major > minor) || !std::isfinite(major))
    throw std::invalid_argument("make_torus: need 0 < minor < major, finite");
  if (nu < 3 || nv < 3) throw std::invalid_argument("make_torus: segment counts must be >= 3");
  TriangleMesh m;
  m.vertices.reserve(static_cast<std::size_t>(nu) * nv);
  for (int i = 0; i < nu; ++i) {
    const double u = 2.0 * kPi * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double v = 2.0 * kPi * j / nv;
      const double rho = major + minor * std::cos(v);
      add_vertex(m, Eigen::Vector3d(rho * std::cos(u), rho * std::sin(u), minor * std::sin(v)));
    }
  }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
      add_quad(m, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
  return m;
}

TriangleMesh make_capsule(double radius, double half_length, int slices, int stacks) {
  if (!(radius > 0.0) || !std::isfinite(radius) || !(half_length >= 0.0) ||
      !std::isfinite(half_length))
    throw std::invalid_argument("make_capsule: need radius > 0 and half_length >= 0, finite");
  if (slices < 3 || stacks < 1)
    throw std::invalid_argument("make_capsule: need slices >= 3 and stacks >= 1");
  TriangleMesh m;
  const int bottom = add_vertex(m, Eigen::Vector3d(0, 0, -half_length - radius));
  // Rings from the bottom cap up to the top cap. With half_length == 0 the two equator
  // rings would coincide, so the equator is emitted once.
  std::vector<int> ring_start;
  auto add_ring = [&](double z, double rho) {
    ring_start.push_back(static_cast<int>(m.vertices.size()));
    for (int s = 0; s < slices; ++s) {
      const double a = 2.0 * kPi * s / slices;
      add_vertex(m, Eigen::Vector3d(rho * std::cos(a), rho * std::sin(a), z));
    }
  };
  for (int k = 1; k <= stacks; ++k) {  // bottom cap, latitude -pi/2 .. 0
    const double phi = -kPi / 2 + kPi / 2 * k / stacks;
    add_ring(-half_length + radius * std::sin(phi), radius * std::cos(phi));
  }
  for (int k = (half_length > 0.0 ? 0 : 1); k < stacks; ++k) {  // top cap, 0 .. pi/2
    const double phi = kPi / 2 * k / stacks;
    add_ring(half_length + radius * std::sin(phi), radius * std::cos(phi));
  }
  const int top = add_vertex(m, Eigen::Vector3d(0, 0, half_length + radius));
  auto at = [&](std::size_t r, int s) { return ring_start[r] + (s % slices); };
  for (int s = 0; s < slices; ++s) m.triangles.push_back({bottom, at(0, s + 1), at(0, s)});
  for (std::size_t r = 0; r + 1 < ring_start.size(); ++r)
    for (int s = 0; s < slices; ++s)
      add_quad(m, at(r, s), at(r, s + 1), at(r + 1, s + 1), at(r + 1, s));
  const std::size_t last = ring_start.size() - 1;
  for (int s = 0; s < slices; ++s) m.triangles.push_back({top, at(last, s), at(last, s + 1)});
  return m;
}

TriangleMesh make_cylinder(double radius, double half_length, int slices) {
  if (!(radius > 0.0) || !std::isfinite(radius) || !(half_length > 0.0) ||
      !std::isfinite(half_length))
    throw std::invalid_argument("make_cylinder: need radius > 0 and half_length > 0, finite");
  if (slices < 3) throw std::invalid_argument("make_cylinder: need slices >= 3");
  TriangleMesh m;
  const int bottom = add_vertex(m, Eigen::Vector3d(0, 0, -half_length));
  const int top = add_vertex(m, Eigen::Vector3d(0, 0, half_length));
  for (const double z : {-half_length, half_length})
    for (int s = 0; s < slices; ++s) {
      const double a = 2.0 * kPi * s / slices;
      add_vertex(m, Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), z));
    }
  auto low = [&](int s) { return 2 + s % slices; };
  auto high = [&](int s) { return 2 + slices + s % slices; };
  for (int s = 0; s < slices; ++s) {
    m.triangles.push_back({bottom, low(s + 1), low(s)});
    add_quad(m, low(s), low(s + 1), high(s + 1), high(s));
    m.triangles.push_back({top, high(s), high(s + 1)});
  }
  return m;
}

}  // namespace medspheres
