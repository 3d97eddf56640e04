#include "medspheres/mesh/mesh_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "medspheres/error.h"
#include "mesh_topology.h"
#include "solid_angle.h"

namespace medspheres {

const char* to_string(Orientation o) {
  switch (o) {
    case Orientation::kOutward:
      return "outward";
    case Orientation::kInward:
      return "inward";
    case Orientation::kInconsistent:
      return "inconsistent";
    case Orientation::kOpen:
      return "open";
  }
  return "unknown";
}

bool MeshReport::is_closed_outward() const {
  if (!closed || component_reports.empty()) return false;
  return std::all_of(component_reports.begin(), component_reports.end(),
                     [](const ComponentReport& c) {
                       return c.orientation == Orientation::kOutward ||
                              (c.orientation == Orientation::kInward && c.cavity);
                     });
}

namespace detail {

void check_indices(const TriangleMesh& mesh) {
  const auto n = static_cast<long long>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k : mesh.triangles[t])
      if (k < 0 || k >= n)
        throw std::invalid_argument("triangle " + std::to_string(t) + " has vertex index " +
                                    std::to_string(k) + " out of range [0, " + std::to_string(n) +
                                    ")");
}

EdgeTable build_edge_table(const TriangleMesh& mesh) {
  EdgeTable table;
  table.half_edges.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (is_collapsed(tri)) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      HalfEdge h;
      h.lo = std::min(a, b);
      h.hi = std::max(a, b);
      h.forward = a < b;
      h.triangle = static_cast<int>(t);
      table.half_edges.push_back(h);
    }
  }
  std::sort(table.half_edges.begin(), table.half_edges.end(),
            [](const HalfEdge& x, const HalfEdge& y) {
              if (x.lo != y.lo) return x.lo < y.lo;
              if (x.hi != y.hi) return x.hi < y.hi;
              return x.triangle < y.triangle;
            });
  for (std::size_t i = 0; i < table.half_edges.size();) {
    std::size_t j = i + 1;
    while (j < table.half_edges.size() && table.half_edges[j].lo == table.half_edges[i].lo &&
           table.half_edges[j].hi == table.half_edges[i].hi)
      ++j;
    table.edge_begin.push_back(i);
    i = j;
  }
  table.edge_begin.push_back(table.half_edges.size());
  return table;
}

std::vector<int> triangle_components(const TriangleMesh& mesh, const EdgeTable& edges,
                                     std::size_t* count) {
  const std::size_t nt = mesh.triangles.size();
  std::vector<int> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (std::size_t e = 0; e + 1 < edges.edge_begin.size(); ++e) {
    const int first = edges.half_edges[edges.edge_begin[e]].triangle;
    for (std::size_t h = edges.edge_begin[e] + 1; h < edges.edge_begin[e + 1]; ++h) {
      const int a = find(first), b = find(edges.half_edges[h].triangle);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // Number components in order of their first triangle.
  std::vector<int> label(nt, -1), comp(nt, -1);
  int next = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    if (is_collapsed(mesh.triangles[t])) continue;
    const int root = find(static_cast<int>(t));
    if (label[root] < 0) label[root] = next++;
    comp[t] = label[root];
  }
  *count = static_cast<std::size_t>(next);
  return comp;
}

}  // namespace detail

namespace {

double triangle_signed_volume(const TriangleMesh& m, std::size_t t) {
  const Eigen::Vector3d& a = m.corner(t, 0);
  const Eigen::Vector3d& b = m.corner(t, 1);
  const Eigen::Vector3d& c = m.corner(t, 2);
  return a.dot(b.cross(c)) / 6.0;
}

bool is_degenerate(const TriangleMesh& m, std::size_t t) {
  const auto& tri = m.triangles[t];
  if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) return true;
  const Eigen::Vector3d n =
      (m.corner(t, 1) - m.corner(t, 0)).cross(m.corner(t, 2) - m.corner(t, 0));
  return n.squaredNorm() == 0.0;
}

// The winding number about p of the triangles of one component: their solid angles
// summed directly over the triangles (no far-field approximation).
double winding_number(const TriangleMesh& m, const std::vector<int>& triangles,
                      const Eigen::Vector3d& p) {
  double sum = 0.0;
  for (int t : triangles) {
    const auto i = static_cast<std::size_t>(t);
    sum += detail::solid_angle(p, m.corner(i, 0), m.corner(i, 1), m.corner(i, 2));
  }
  return sum / (4.0 * 3.14159265358979323846);
}

// A point of a component that stands for it in containment tests: the centroid of its
// largest triangle (first in order on ties), which lies on no other component unless
// the two overlap.
Eigen::Vector3d interior_point(const TriangleMesh& m, const std::vector<int>& triangles) {
  double best = -1.0;
  std::size_t pick = static_cast<std::size_t>(triangles.front());
  for (int t : triangles) {
    const auto i = static_cast<std::size_t>(t);
    const double area2 =
        (m.corner(i, 1) - m.corner(i, 0)).cross(m.corner(i, 2) - m.corner(i, 0)).squaredNorm();
    if (area2 > best) {
      best = area2;
      pick = i;
    }
  }
  return (m.corner(pick, 0) + m.corner(pick, 1) + m.corner(pick, 2)) / 3.0;
}

// For each component c with query[c], how many other components d with solid[d]
// contain it (|winding number of d| > 0.5 at c's interior_point); 0 for the others.
std::vector<std::size_t> containment_depth(const TriangleMesh& m,
                                           const std::vector<std::vector<int>>& members,
                                           const std::vector<char>& solid,
                                           const std::vector<char>& query) {
  const std::size_t n = members.size();
  std::vector<std::size_t> depth(n, 0);
  if (std::none_of(query.begin(), query.end(), [](char q) { return q != 0; })) return depth;
  std::vector<Eigen::AlignedBox3d> box(n);
  for (std::size_t d = 0; d < n; ++d)
    if (solid[d])
      for (int t : members[d])
        for (int k = 0; k < 3; ++k) box[d].extend(m.corner(static_cast<std::size_t>(t), k));
  for (std::size_t c = 0; c < n; ++c) {
    if (!query[c] || members[c].empty()) continue;
    const Eigen::Vector3d p = interior_point(m, members[c]);
    for (std::size_t d = 0; d < n; ++d) {
      if (d == c || !solid[d] || !box[d].contains(p)) continue;
      depth[c] += std::abs(winding_number(m, members[d], p)) > 0.5;
    }
  }
  return depth;
}

// The triangles of each component (comp: a triangle's component, -1 for none).
std::vector<std::vector<int>> component_members(const std::vector<int>& comp, std::size_t ncomp) {
  std::vector<std::vector<int>> members(ncomp);
  for (std::size_t t = 0; t < comp.size(); ++t)
    if (comp[t] >= 0) members[comp[t]].push_back(static_cast<int>(t));
  return members;
}

// The vertices the triangles use, the unused ones and the used ones' bounding box.
void count_vertices(const TriangleMesh& mesh, MeshReport& r) {
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& tri : mesh.triangles)
    for (int k : tri) used[static_cast<std::size_t>(k)] = 1;
  Eigen::AlignedBox3d box;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (!used[v]) continue;
    ++r.vertices;
    box.extend(mesh.vertices[v]);
  }
  r.unreferenced_vertices = mesh.vertices.size() - r.vertices;
  if (!box.isEmpty()) {
    r.bbox_min = box.min();
    r.bbox_max = box.max();
  }
}

// Boundary, non-manifold and inconsistently wound edges, over the mesh and per component;
// returns per component whether an edge of it is wound inconsistently.
std::vector<char> count_edges(const detail::EdgeTable& edges, const std::vector<int>& comp,
                              MeshReport& r) {
  std::vector<char> inconsistent(r.component_reports.size(), 0);
  r.edges = edges.num_edges();
  for (std::size_t e = 0; e < edges.num_edges(); ++e) {
    const std::size_t b = edges.edge_begin[e], n = edges.edge_begin[e + 1] - b;
    // Every triangle at an edge lies in the same component, by construction.
    ComponentReport& c = r.component_reports[comp[edges.half_edges[b].triangle]];
    if (n == 1) {
      ++r.boundary_edges;
      ++c.boundary_edges;
    } else if (n >= 3) {
      ++r.nonmanifold_edges;
      ++c.nonmanifold_edges;
    } else if (edges.half_edges[b].forward == edges.half_edges[b + 1].forward) {
      ++r.inconsistent_edges;
      inconsistent[comp[edges.half_edges[b].triangle]] = 1;
    }
  }
  return inconsistent;
}

// Degenerate and collapsed triangles, and the signed volume, over the mesh and per
// component.
void count_triangles(const TriangleMesh& mesh, const std::vector<int>& comp, MeshReport& r) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (is_degenerate(mesh, t)) ++r.degenerate_triangles;
    if (comp[t] < 0) {
      ++r.collapsed_triangles;  // zero volume, no component
      continue;
    }
    const double v = triangle_signed_volume(mesh, t);
    r.signed_volume += v;
    ComponentReport& c = r.component_reports[comp[t]];
    ++c.triangles;
    c.signed_volume += v;
  }
}

// Each component's closedness, orientation and whether it is a cavity: an inward component
// at odd nesting depth (see orient_mesh).
void classify_components(const TriangleMesh& mesh, const std::vector<int>& comp,
                         const std::vector<char>& inconsistent, MeshReport& r) {
  const std::size_t ncomp = r.component_reports.size();
  std::vector<char> solid(ncomp, 0), inward(ncomp, 0);
  for (std::size_t i = 0; i < ncomp; ++i) {
    ComponentReport& c = r.component_reports[i];
    c.closed = c.boundary_edges == 0 && c.nonmanifold_edges == 0;
    if (!c.closed)
      c.orientation = Orientation::kOpen;
    else if (inconsistent[i])
      c.orientation = Orientation::kInconsistent;
    else
      c.orientation = c.signed_volume >= 0.0 ? Orientation::kOutward : Orientation::kInward;
    solid[i] = c.orientation == Orientation::kOutward || c.orientation == Orientation::kInward;
    inward[i] = c.orientation == Orientation::kInward;
  }
  if (std::none_of(inward.begin(), inward.end(), [](char x) { return x != 0; })) return;
  const std::vector<std::size_t> depth =
      containment_depth(mesh, component_members(comp, ncomp), solid, inward);
  for (std::size_t i = 0; i < ncomp; ++i)
    r.component_reports[i].cavity = inward[i] && depth[i] % 2 == 1;
}

}  // namespace

MeshReport analyze_mesh(const TriangleMesh& mesh) {
  detail::check_indices(mesh);
  MeshReport r;
  r.triangles = mesh.triangles.size();
  count_vertices(mesh, r);
  const detail::EdgeTable edges = detail::build_edge_table(mesh);
  std::size_t ncomp = 0;
  const std::vector<int> comp = detail::triangle_components(mesh, edges, &ncomp);
  r.components = ncomp;
  r.component_reports.assign(ncomp, ComponentReport{});
  const std::vector<char> inconsistent = count_edges(edges, comp, r);
  count_triangles(mesh, comp, r);
  r.closed = r.boundary_edges == 0 && r.nonmanifold_edges == 0 && r.triangles > 0;
  classify_components(mesh, comp, inconsistent, r);
  return r;
}

// Each directed edge a -> b as one 64-bit key, sorted: the mesh is closed and consistent
// exactly when no key repeats and every key's reverse is present. (An edge with one use
// lacks its reverse; two uses in one direction repeat a key; three or more uses repeat a
// key or, with two in one direction and one back, both.)
bool is_closed_consistent(const TriangleMesh& mesh) {
  detail::check_indices(mesh);
  if (mesh.triangles.empty()) return false;
  const auto key = [](int a, int b) {
    return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32 |
           static_cast<std::uint32_t>(b);
  };
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    if (!detail::is_collapsed(t))
      for (int k = 0; k < 3; ++k) directed.push_back(key(t[k], t[(k + 1) % 3]));
  std::sort(directed.begin(), directed.end());
  if (std::adjacent_find(directed.begin(), directed.end()) != directed.end()) return false;
  return std::all_of(directed.begin(), directed.end(), [&](std::uint64_t e) {
    const auto a = static_cast<int>(e >> 32), b = static_cast<int>(e & 0xffffffffu);
    return std::binary_search(directed.begin(), directed.end(), key(b, a));
  });
}

namespace {

// Per triangle, its manifold edges (as edge ids, ascending; -1 after the last) for the
// breadth-first walk of orient_components, and per component whether an edge of it has
// three or more triangles. A triangle has three edges, so three slots hold them all, in
// one flat array rather than a vector per triangle.
std::vector<std::array<int, 3>> manifold_edges(const detail::EdgeTable& edges,
                                               const std::vector<int>& comp, std::size_t nt,
                                               std::vector<char>& comp_nonmanifold) {
  std::vector<std::array<int, 3>> tri_edges(nt, {-1, -1, -1});
  const auto add_edge = [&](int t, std::size_t e) {
    for (int& slot : tri_edges[static_cast<std::size_t>(t)])
      if (slot < 0) {
        slot = static_cast<int>(e);
        return;
      }
  };
  for (std::size_t e = 0; e < edges.num_edges(); ++e) {
    const std::size_t b = edges.edge_begin[e], n = edges.edge_begin[e + 1] - b;
    if (n >= 3) comp_nonmanifold[comp[edges.half_edges[b].triangle]] = 1;
    if (n == 2) {
      add_edge(edges.half_edges[b].triangle, e);
      if (edges.half_edges[b + 1].triangle != edges.half_edges[b].triangle)
        add_edge(edges.half_edges[b + 1].triangle, e);
    }
  }
  return tri_edges;
}

// Winds every manifold, orientable component consistently (its smaller set of triangles
// flipped), counting the flips in fix; returns per component whether it was (0: a
// non-manifold or non-orientable component, left as it is).
std::vector<char> orient_components(TriangleMesh& mesh, const detail::EdgeTable& edges,
                                    const std::vector<int>& comp,
                                    const std::vector<std::vector<int>>& members,
                                    OrientationFix& fix) {
  const std::size_t nt = mesh.triangles.size(), ncomp = members.size();
  std::vector<char> comp_ok(ncomp, 1), comp_nonmanifold(ncomp, 0);
  const std::vector<std::array<int, 3>> tri_edges =
      manifold_edges(edges, comp, nt, comp_nonmanifold);
  std::vector<signed char> flip(nt, -1);  // 0 keep, 1 flip, -1 not yet visited
  for (std::size_t c = 0; c < ncomp; ++c) {
    if (comp_nonmanifold[c]) {
      comp_ok[c] = 0;
      continue;
    }
    const int seed = members[c].front();
    flip[seed] = 0;
    std::queue<int> q;
    q.push(seed);
    while (!q.empty() && comp_ok[c]) {
      const int t = q.front();
      q.pop();
      for (int e : tri_edges[static_cast<std::size_t>(t)]) {
        if (e < 0) break;
        const detail::HalfEdge& h0 = edges.half_edges[edges.edge_begin[e]];
        const detail::HalfEdge& h1 = edges.half_edges[edges.edge_begin[e] + 1];
        const detail::HalfEdge& mine = h0.triangle == t ? h0 : h1;
        const detail::HalfEdge& other = h0.triangle == t ? h1 : h0;
        // After flipping, the two half-edges must run in opposite directions.
        const bool my_dir = mine.forward != (flip[t] == 1);
        const int u = other.triangle;
        const signed char want = (other.forward == !my_dir) ? 0 : 1;
        if (flip[u] < 0) {
          flip[u] = want;
          q.push(u);
        } else if (flip[u] != want) {
          comp_ok[c] = 0;  // non-orientable (or a degenerate self-contradiction)
        }
      }
    }
    if (!comp_ok[c]) continue;
    std::size_t flipped = 0;
    for (int t : members[c]) flipped += flip[t] == 1;
    const bool invert = 2 * flipped > members[c].size();  // flip the smaller set
    for (int t : members[c]) {
      if ((flip[t] == 1) != invert) {
        std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
        ++fix.triangles_flipped_for_consistency;
      }
    }
  }
  return comp_ok;
}

// Turns outward the closed, consistently wound components (comp_ok) with negative volume
// that bound material: those an even number of the other closed components contain (see
// mesh_report.h); one at odd depth is a cavity, correctly wound inward.
void turn_solids_outward(TriangleMesh& mesh, const detail::EdgeTable& edges,
                         const std::vector<int>& comp, const std::vector<std::vector<int>>& members,
                         const std::vector<char>& comp_ok, OrientationFix& fix) {
  const std::size_t ncomp = members.size();
  std::vector<double> vol(ncomp, 0.0);
  std::vector<char> closed(ncomp, 1);
  for (std::size_t e = 0; e < edges.num_edges(); ++e) {
    const std::size_t n = edges.edge_begin[e + 1] - edges.edge_begin[e];
    if (n != 2) closed[comp[edges.half_edges[edges.edge_begin[e]].triangle]] = 0;
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (comp[t] >= 0) vol[comp[t]] += triangle_signed_volume(mesh, t);
  std::vector<char> solid(ncomp, 0), inward(ncomp, 0);
  for (std::size_t c = 0; c < ncomp; ++c) {
    solid[c] = comp_ok[c] && closed[c];
    inward[c] = solid[c] && vol[c] < 0.0;
  }
  const std::vector<std::size_t> depth = containment_depth(mesh, members, solid, inward);
  std::vector<std::size_t> to_flip;
  for (std::size_t c = 0; c < ncomp; ++c)
    if (inward[c] && depth[c] % 2 == 0) to_flip.push_back(c);
  for (std::size_t c : to_flip) {
    for (int t : members[c]) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    ++fix.components_flipped_outward;
  }
}

}  // namespace

// Cavities. A hollow solid (a ball with a spherical void) has an inner shell wound
// inward: its negative volume is what makes the total the solid's volume. So a closed,
// consistently wound component at nesting depth 0 (outermost), 2, ... bounds material and
// must face out; at odd depth it bounds a cavity and already faces the right way. The
// containment test sums the solid angles of D's triangles directly, with no far-field
// approximation, and takes the absolute value, so D's own orientation does not matter.
OrientationFix orient_mesh(TriangleMesh& mesh) {
  detail::check_indices(mesh);
  OrientationFix fix;
  const detail::EdgeTable edges = detail::build_edge_table(mesh);
  std::size_t ncomp = 0;
  const std::vector<int> comp = detail::triangle_components(mesh, edges, &ncomp);
  const std::vector<std::vector<int>> members = component_members(comp, ncomp);
  const std::vector<char> comp_ok = orient_components(mesh, edges, comp, members, fix);
  turn_solids_outward(mesh, edges, comp, members, comp_ok, fix);
  return fix;
}

std::vector<std::vector<int>> boundary_loops(const TriangleMesh& mesh) {
  detail::check_indices(mesh);
  const detail::EdgeTable edges = detail::build_edge_table(mesh);
  // Boundary edges, directed as in their triangle, sorted by tail: out[v] lists the
  // edges leaving v, lowest first.
  std::vector<std::pair<int, int>> directed;
  for (std::size_t e = 0; e < edges.num_edges(); ++e) {
    if (edges.edge_begin[e + 1] - edges.edge_begin[e] != 1) continue;
    const detail::HalfEdge& h = edges.half_edges[edges.edge_begin[e]];
    directed.emplace_back(h.forward ? h.lo : h.hi, h.forward ? h.hi : h.lo);
  }
  std::sort(directed.begin(), directed.end());
  std::vector<char> used(directed.size(), 0);
  // first[v]: index of the first edge leaving v in `directed` (or directed.size()).
  const auto first_leaving = [&](int v) {
    return static_cast<std::size_t>(
        std::lower_bound(directed.begin(), directed.end(), std::make_pair(v, INT32_MIN)) -
        directed.begin());
  };
  std::vector<std::vector<int>> loops;
  for (std::size_t start = 0; start < directed.size(); ++start) {
    if (used[start]) continue;
    std::vector<int> loop;
    std::size_t e = start;
    for (;;) {
      used[e] = 1;
      loop.push_back(directed[e].first);
      const int head = directed[e].second;
      if (head == directed[start].first) break;  // closed
      std::size_t next = first_leaving(head);
      while (next < directed.size() && directed[next].first == head && used[next]) ++next;
      if (next >= directed.size() || directed[next].first != head) {
        loop.push_back(head);  // open chain: keep its last vertex
        break;
      }
      e = next;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

void check_mesh_usable(const TriangleMesh& mesh, const std::string& source) {
  if (mesh.triangles.empty())
    throw InputError(ErrorKind::kNoInterior, source, "the mesh has no triangles");
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!mesh.vertices[v].allFinite()) {
      std::ostringstream msg;
      msg << "vertex " << v << " has a non-finite coordinate (" << mesh.vertices[v].x() << ", "
          << mesh.vertices[v].y() << ", " << mesh.vertices[v].z() << ")";
      throw InputError(source, msg.str());
    }
    if (mesh.vertices[v].cwiseAbs().maxCoeff() > kMaxCoordinate) {
      std::ostringstream msg;
      msg << "vertex " << v << " has a coordinate beyond " << kMaxCoordinate << " in magnitude ("
          << mesh.vertices[v].x() << ", " << mesh.vertices[v].y() << ", " << mesh.vertices[v].z()
          << "): squared lengths would overflow; rescale the mesh";
      throw InputError(source, msg.str());
    }
  }
  try {
    detail::check_indices(mesh);
  } catch (const std::invalid_argument& e) {
    throw InputError(source, e.what());
  }
  std::size_t degenerate = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) degenerate += is_degenerate(mesh, t);
  if (degenerate == mesh.triangles.size())
    throw InputError(source,
                     (degenerate == 1 ? std::string("its one triangle is")
                                      : "all " + std::to_string(degenerate) + " triangles are") +
                         " degenerate (zero area)");
}

}  // namespace medspheres
