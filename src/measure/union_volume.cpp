// The one translation unit of medspheres that includes CGAL's triangulations.
//
// Pipeline: validate and rescale the balls by a power of two; drop duplicates and balls
// sharing a centre with a larger one; build the regular triangulation of the weighted
// centres; list its simplices of every dimension with their cofaces; classify them into
// the alpha = 0 complex with exact predicates; sum the closed-form measures of
// ball_intersection.h over the complex; collect v-points and lone-edge circles.
//
// Classification (Edelsbrunner 1995; the rule of CGAL's Fixed_alpha_shape_3, extended to
// triangulations of dimension 1 and 2). A simplex s of the regular triangulation is in K
// iff a simplex of one dimension more that contains it is in K, or the smallest sphere
// orthogonal to its balls has power radius rho_s <= 0 and is not "attached": no vertex u
// that forms a simplex of one dimension more with s has pi_u(z_s) < rho_s at the centre
// z_s of that sphere. Checking those vertices suffices, because the face of the power
// diagram dual to s is cut out, inside the affine hull where the balls of s have equal
// power, by exactly the half-spaces of those vertices. A top-dimensional simplex is
// never attached (the triangulation is regular). Touching (rho_s = 0, or z_s on the
// boundary of the dual face) counts as meeting; it changes no measure. Because a simplex
// with a coface in K is in K, K is a simplicial complex whatever the ties.

#include "medspheres/measure/union_volume.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <climits>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_3.h>
#include <CGAL/Regular_triangulation_cell_base_3.h>
#include <CGAL/Regular_triangulation_vertex_base_3.h>
#include <CGAL/Triangulation_data_structure_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <Eigen/Geometry>

#include "ball_intersection.h"
#include "medspheres/assert.h"
#include "medspheres/error.h"

// The method and its exactness (union_volume.h states the contract).
// Exact volume and boundary area of a union of balls (paper §4.2), and the dual complex
// of its power-diagram decomposition, which the dilation step (paper §5.1) walks.
//
// Method. The balls B_i = (c_i, r_i) are weighted points (c_i, r_i^2). Their regular
// triangulation is dual to the power diagram; the dual complex K is the subcomplex of
// simplices s whose balls and power cells have a common point,
// (B_i n P_i for i in s) != empty, i.e. the weighted alpha complex at alpha = 0
// (Edelsbrunner 1995). Then
//   vol(union) = sum over s in K of (-1)^dim(s) vol(intersection of the balls of s),
// and the same alternating sum of the areas of the sphere pieces inside the other balls
// of each simplex gives the boundary area. The intersections of two, three and four
// balls have closed forms (derived in src/measure/ball_intersection.h).
//
// Frame and units: centres and radii are in the caller's frame and units (frame M, as
// in sphere_set.h). Volumes are in units^3, areas in units^2, positions in frame M.
//
// Exactness. Which simplices are in K, which balls are hidden and which triple points
// are v-points is decided with exact predicates (CGAL, filtered exact arithmetic) on the
// weighted points (c_i, w_i), w_i = r_i^2 rounded to double: exactly, for balls whose
// radii differ from the given ones by at most half a unit in the last place. The measures
// are then evaluated in double precision by closed forms without case distinctions on
// rounded values, so they are continuous in the input, tangent and almost tangent balls
// included. The measure of a k-simplex of K has an absolute error of a few
// eps (k + 1) 4 pi r^3 (area: r^2), eps = 2^-52 and r its largest radius (the tests
// allow 16 times that); against independent integrations of small sets the relative
// error of the volume and of the area is near 1e-15.
//
// Degenerate input. Empty input has volume and area 0. A ball with the same centre and
// radius as an earlier one is a duplicate: it is dropped and listed in `duplicates`.
// A ball that lies in the union of the others (for instance in a single larger ball)
// gets no vertex in K, contributes nothing and is listed in `hidden`; one that reaches
// the boundary of the union only in a set of measure zero (say, it touches a larger ball
// from inside) may keep its vertex, which changes no measure. Collinear and coplanar
// centres give a triangulation of dimension 1 or 2, cospherical ones a degenerate one
// that CGAL resolves by symbolic perturbation; the formula holds in every case.
//
// Input errors: a non-finite coordinate or a radius that is not finite and > 0 throws
// InputError with source "sphere set" and the index of the ball. More than INT_MAX balls
// throws std::invalid_argument.
//
// Thread safety: a UnionOfBalls is immutable after construction; its const members may
// be called from any number of threads.

namespace medspheres {

namespace {

// Epick: filtered exact predicates, double constructions. Only predicates are used on
// the triangulation; every construction below is our own double arithmetic.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using WeightedPoint = Kernel::Weighted_point_3;
using VertexBase =
    CGAL::Triangulation_vertex_base_with_info_3<int, Kernel,
                                                CGAL::Regular_triangulation_vertex_base_3<Kernel>>;
using CellBase =
    CGAL::Regular_triangulation_cell_base_3<Kernel, CGAL::Triangulation_cell_base_3<Kernel>,
                                            CGAL::Discard_hidden_points>;
using Tds = CGAL::Triangulation_data_structure_3<VertexBase, CellBase, CGAL::Sequential_tag>;
using Regular = CGAL::Regular_triangulation_3<Kernel, Tds>;

constexpr double kPi = 3.141592653589793238462643383279502884;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Neumaier's compensated sum: the inclusion-exclusion terms alternate in sign and the
// total can be much smaller than the sum of the balls' volumes.
class CompensatedSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    compensation_ += std::abs(sum_) >= std::abs(x) ? (sum_ - t) + x : (x - t) + sum_;
    sum_ = t;
  }
  double value() const { return sum_ + compensation_; }

 private:
  double sum_ = 0.0;
  double compensation_ = 0.0;
};

void check_input(const std::vector<Sphere>& balls) {
  if (balls.size() > static_cast<std::size_t>(INT_MAX))
    throw std::invalid_argument("UnionOfBalls: more than INT_MAX balls");
  for (std::size_t i = 0; i < balls.size(); ++i) {
    const Sphere& s = balls[i];
    if (!s.center.allFinite()) {
      std::ostringstream msg;
      msg << "sphere " << i << " has a non-finite centre (" << s.center.x() << ", " << s.center.y()
          << ", " << s.center.z() << ")";
      throw InputError("sphere set", msg.str());
    }
    if (!std::isfinite(s.radius) || !(s.radius > 0.0)) {
      std::ostringstream msg;
      msg << "sphere " << i << " has radius " << s.radius << " (must be finite and > 0)";
      throw InputError("sphere set", msg.str());
    }
  }
}

// The binary exponent e with max(|coordinate|, radius) in [2^(e-1), 2^e). Dividing by 2^e
// is exact, keeps every product of up to six lengths far from overflow and underflow,
// and makes the result exactly equivariant under scaling by powers of two.
int scale_exponent(const std::vector<Sphere>& balls) {
  int exponent = INT_MIN;
  for (const Sphere& s : balls) {
    for (const double v :
         {std::abs(s.center.x()), std::abs(s.center.y()), std::abs(s.center.z()), s.radius}) {
      if (v == 0.0) continue;
      int e = 0;
      std::frexp(v, &e);
      exponent = std::max(exponent, e);
    }
  }
  return exponent;
}

struct Ball {
  Eigen::Vector3d c;
  double r = 0.0;
};

// Simplices of one dimension: N vertices each, as ascending vertex ids, the list in
// lexicographic order.
template <int N>
struct Simplices {
  std::vector<std::array<int, N>> v;
  std::vector<unsigned char> in_complex;
  std::vector<unsigned char> coface_in_complex;  // some simplex containing it is in K
  std::vector<std::array<int, N>> face;          // face[s][q]: the face opposite vertex q
};

// Exact predicates on the weighted points, by vertex id.
class Predicates {
 public:
  explicit Predicates(const std::vector<WeightedPoint>& points) : p_(points) {}

  // Sign of the power radius rho of the smallest sphere orthogonal to the balls of s.
  CGAL::Comparison_result radius_sign(const std::array<int, 1>& s) const {
    return compare_(p_[s[0]], 0.0);
  }
  CGAL::Comparison_result radius_sign(const std::array<int, 2>& s) const {
    return compare_(p_[s[0]], p_[s[1]], 0.0);
  }
  CGAL::Comparison_result radius_sign(const std::array<int, 3>& s) const {
    return compare_(p_[s[0]], p_[s[1]], p_[s[2]], 0.0);
  }
  CGAL::Comparison_result radius_sign(const std::array<int, 4>& s) const {
    return compare_(p_[s[0]], p_[s[1]], p_[s[2]], p_[s[3]], 0.0);
  }

  // True when pi_u(z_s) < rho_s: vertex u attaches s (see the file comment).
  bool attaches(const std::array<int, 1>& s, int u) const {
    return side_(p_[s[0]], p_[u]) == CGAL::ON_BOUNDED_SIDE;
  }
  bool attaches(const std::array<int, 2>& s, int u) const {
    return side_(p_[s[0]], p_[s[1]], p_[u]) == CGAL::ON_BOUNDED_SIDE;
  }
  bool attaches(const std::array<int, 3>& s, int u) const {
    return side_(p_[s[0]], p_[s[1]], p_[s[2]], p_[u]) == CGAL::ON_BOUNDED_SIDE;
  }

 private:
  const std::vector<WeightedPoint>& p_;
  Kernel::Compare_weighted_squared_radius_3 compare_;
  Kernel::Power_side_of_bounded_power_sphere_3 side_;
};

template <int N>
void classify_top(Simplices<N>& top, const Predicates& pred,
                  std::vector<signed char>& radius_sign) {
  const std::size_t count = top.v.size();
  top.in_complex.resize(count);
  top.coface_in_complex.assign(count, 0);
  radius_sign.resize(count);
  for (std::size_t s = 0; s < count; ++s) {
    const CGAL::Comparison_result sign = pred.radius_sign(top.v[s]);
    radius_sign[s] = static_cast<signed char>(sign);
    top.in_complex[s] = sign != CGAL::LARGER;
  }
}

// Lists the faces of the simplices in \p upper, fills upper.face, and classifies the
// faces. \p cofaces, when given, receives the (up to two) simplices of \p upper that
// contain each face, -1 for none.
template <int N>
void build_faces(Simplices<N>& upper, Simplices<N - 1>& lower, int vertex_count,
                 const Predicates& pred, std::vector<std::array<int, 2>>* cofaces) {
  struct Record {
    std::array<int, N - 1> key;
    int opposite;
    int parent;
    int local;
  };
  // Bucket the (face, coface) records by the face's first vertex, then sort each bucket
  // (a few dozen records): the lexicographic order of a global sort, at a fraction of
  // its cost.
  std::vector<std::size_t> bucket(static_cast<std::size_t>(vertex_count) + 1, 0);
  for (const std::array<int, N>& simplex : upper.v)
    for (int q = 0; q < N; ++q) ++bucket[simplex[q == 0 ? 1 : 0] + 1];
  std::partial_sum(bucket.begin(), bucket.end(), bucket.begin());
  std::vector<Record> records(upper.v.size() * N);
  std::vector<std::size_t> next(bucket.begin(), bucket.end() - 1);
  for (std::size_t s = 0; s < upper.v.size(); ++s) {
    for (int q = 0; q < N; ++q) {
      Record rec;
      for (int k = 0, m = 0; k < N; ++k)
        if (k != q) rec.key[m++] = upper.v[s][k];
      rec.opposite = upper.v[s][q];
      rec.parent = static_cast<int>(s);
      rec.local = q;
      records[next[rec.key[0]]++] = rec;
    }
  }
  for (int v = 0; v < vertex_count; ++v)
    std::sort(records.begin() + bucket[v], records.begin() + bucket[v + 1],
              [](const Record& a, const Record& b) {
                return std::tie(a.key, a.opposite) < std::tie(b.key, b.opposite);
              });

  upper.face.resize(upper.v.size());
  lower.v.clear();
  lower.in_complex.clear();
  lower.coface_in_complex.clear();
  if (cofaces != nullptr) cofaces->clear();
  for (std::size_t i = 0; i < records.size();) {
    std::size_t j = i;
    while (j < records.size() && records[j].key == records[i].key) ++j;
    const int id = static_cast<int>(lower.v.size());
    const std::array<int, N - 1>& key = records[i].key;
    bool coface = false;
    for (std::size_t k = i; k < j; ++k) {
      upper.face[records[k].parent][records[k].local] = id;
      coface = coface || upper.in_complex[records[k].parent] != 0;
    }
    bool in = coface;
    if (!in && pred.radius_sign(key) != CGAL::LARGER) {
      in = true;
      for (std::size_t k = i; k < j && in; ++k) in = !pred.attaches(key, records[k].opposite);
    }
    lower.v.push_back(key);
    lower.in_complex.push_back(in);
    lower.coface_in_complex.push_back(coface);
    if (cofaces != nullptr) {
      MEDSPHERES_ASSERT(j - i <= 2);
      std::array<int, 2> parents{-1, -1};
      for (std::size_t k = i; k < j && k < i + 2; ++k) parents[k - i] = records[k].parent;
      cofaces->push_back(parents);
    }
    i = j;
  }
}

// Orientation sign of an ascending rearrangement of a positively oriented tuple.
int sorted_orientation(std::array<int, 4>& ids) {
  int inversions = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) inversions += ids[a] > ids[b] ? 1 : 0;
  std::sort(ids.begin(), ids.end());
  return inversions % 2 == 0 ? 1 : -1;
}

// The input after rescaling, with duplicates and concentric smaller balls set aside.
struct Prepared {
  int exponent = 0;         // balls are the input divided by 2^exponent
  std::vector<Ball> ball;   // by input index
  std::vector<int> kept;    // ascending: the balls that go to the triangulation
  std::vector<int> hidden;  // concentric with a larger ball
  std::vector<int> duplicates;
};

Prepared prepare(const std::vector<Sphere>& input) {
  Prepared p;
  const int n = static_cast<int>(input.size());
  p.exponent = scale_exponent(input);
  p.ball.resize(n);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) p.ball[i].c[k] = std::ldexp(input[i].center[k], -p.exponent);
    p.ball[i].r = std::ldexp(input[i].radius, -p.exponent);
  }
  // Equal centres become adjacent, the largest radius (then the smallest index) first.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const Eigen::Vector3d &ca = p.ball[a].c, &cb = p.ball[b].c;
    return std::make_tuple(ca.x(), ca.y(), ca.z(), -p.ball[a].r, a) <
           std::make_tuple(cb.x(), cb.y(), cb.z(), -p.ball[b].r, b);
  });
  for (int i = 0; i < n;) {
    int j = i + 1;
    while (j < n && p.ball[order[j]].c == p.ball[order[i]].c) ++j;
    p.kept.push_back(order[i]);
    for (int k = i + 1; k < j; ++k)
      (p.ball[order[k]].r == p.ball[order[i]].r ? p.duplicates : p.hidden).push_back(order[k]);
    i = j;
  }
  std::sort(p.kept.begin(), p.kept.end());
  std::sort(p.duplicates.begin(), p.duplicates.end());
  return p;
}

// The regular triangulation's simplices of every dimension, classified. Vertex ids
// follow the ball indices, so ascending ids are ascending indices.
struct Complex {
  int dimension = -1;
  std::vector<int> ball_of;             // vertex id -> ball index
  std::vector<WeightedPoint> weighted;  // by vertex id
  Simplices<1> verts;
  Simplices<2> edges;
  Simplices<3> tris;
  Simplices<4> tets;
  std::vector<signed char> top_sign;            // sign of rho of each top-dimensional simplex
  std::vector<signed char> tet_orient;          // orientation of each tetrahedron's sorted tuple
  std::vector<std::array<int, 2>> tri_cofaces;  // tetrahedra of each triangle, -1: none
};

// Inserts the kept balls as weighted points (c, r^2) with their indices, in CGAL's
// spatially sorted order.
void triangulate(const Prepared& p, Regular& rt) {
  std::vector<std::pair<WeightedPoint, int>> points;
  points.reserve(p.kept.size());
  for (const int i : p.kept) {
    const Eigen::Vector3d& c = p.ball[i].c;
    points.emplace_back(
        WeightedPoint(Kernel::Point_3(c.x(), c.y(), c.z()), p.ball[i].r * p.ball[i].r), i);
  }
  rt.insert(points.begin(), points.end());
}

// Lists and classifies the simplices of \p rt; kept balls without a vertex (redundant
// weighted points, which have no power cell) are appended to \p hidden.
Complex classify(const Regular& rt, const Prepared& p, std::vector<int>& hidden) {
  Complex k;
  k.dimension = rt.dimension();
  for (auto v = rt.finite_vertices_begin(); v != rt.finite_vertices_end(); ++v)
    k.ball_of.push_back(v->info());
  std::sort(k.ball_of.begin(), k.ball_of.end());
  std::vector<int> vertex_of(p.ball.size(), -1);
  const int nv = static_cast<int>(k.ball_of.size());
  for (int id = 0; id < nv; ++id) vertex_of[k.ball_of[id]] = id;
  for (const int i : p.kept)
    if (vertex_of[i] < 0) hidden.push_back(i);
  k.weighted.resize(nv);
  for (auto v = rt.finite_vertices_begin(); v != rt.finite_vertices_end(); ++v)
    k.weighted[vertex_of[v->info()]] = v->point();
  const Predicates pred(k.weighted);
  auto id = [&](Regular::Vertex_handle v) { return vertex_of[v->info()]; };

  if (k.dimension == 3) {
    // Simplices are listed in lexicographic order; carry the orientations along.
    std::vector<std::pair<std::array<int, 4>, signed char>> cells;
    cells.reserve(rt.number_of_finite_cells());
    for (auto c = rt.finite_cells_begin(); c != rt.finite_cells_end(); ++c) {
      std::array<int, 4> t{id(c->vertex(0)), id(c->vertex(1)), id(c->vertex(2)), id(c->vertex(3))};
      const int orientation = sorted_orientation(t);  // CGAL's cells are positively oriented
      cells.emplace_back(t, static_cast<signed char>(orientation));
    }
    std::sort(cells.begin(), cells.end());
    for (const auto& cell : cells) {
      k.tets.v.push_back(cell.first);
      k.tet_orient.push_back(cell.second);
    }
    classify_top(k.tets, pred, k.top_sign);
    build_faces(k.tets, k.tris, nv, pred, &k.tri_cofaces);
    build_faces(k.tris, k.edges, nv, pred, nullptr);
    build_faces(k.edges, k.verts, nv, pred, nullptr);
  } else if (k.dimension == 2) {  // coplanar centres: the facets are the triangles
    for (auto f = rt.finite_facets_begin(); f != rt.finite_facets_end(); ++f) {
      std::array<int, 3> t{};
      for (int q = 0, m = 0; q < 4; ++q)
        if (q != f->second) t[m++] = id(f->first->vertex(q));
      std::sort(t.begin(), t.end());
      k.tris.v.push_back(t);
    }
    std::sort(k.tris.v.begin(), k.tris.v.end());
    classify_top(k.tris, pred, k.top_sign);
    build_faces(k.tris, k.edges, nv, pred, nullptr);
    build_faces(k.edges, k.verts, nv, pred, nullptr);
  } else if (k.dimension == 1) {  // collinear centres
    for (auto e = rt.finite_edges_begin(); e != rt.finite_edges_end(); ++e) {
      std::array<int, 2> t{id(e->first->vertex(e->second)), id(e->first->vertex(e->third))};
      std::sort(t.begin(), t.end());
      k.edges.v.push_back(t);
    }
    std::sort(k.edges.v.begin(), k.edges.v.end());
    classify_top(k.edges, pred, k.top_sign);
    build_faces(k.edges, k.verts, nv, pred, nullptr);
  } else if (k.dimension == 0) {  // one distinct centre
    k.verts.v.push_back({0});
    classify_top(k.verts, pred, k.top_sign);
  }
  return k;
}

// Inclusion-exclusion over K, in the order of the simplex lists (vertices, edges,
// triangles, tetrahedra: the order of the compensated sums), collecting the simplices of K,
// the v-points and the lone-edge circles as ball indices in the input's units.
class ComplexSum {
 public:
  ComplexSum(const Prepared& p, const Complex& k, std::vector<int> hidden_balls)
      : hidden(std::move(hidden_balls)),
        p_(p),
        k_(k),
        pred_(k.weighted),
        unscale_(std::ldexp(1.0, p.exponent)) {}

  void add_vertices();
  void add_edges();
  void add_triangles();
  void add_tetrahedra();

  double volume() const { return std::ldexp(volume_.value(), 3 * p_.exponent); }
  double area() const { return std::ldexp(area_.value(), 2 * p_.exponent); }

  std::vector<int> hidden;
  std::vector<int> vertices;
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 4>> tetrahedra;
  std::vector<VPoint> v_points;
  std::vector<EdgeCircle> lone_circles;

 private:
  void add(const detail::Measure& m, int sign) {
    volume_.add(sign * m.volume);
    area_.add(sign * m.area);
  }
  const Eigen::Vector3d& centre(int v) const { return p_.ball[k_.ball_of[v]].c; }
  double radius(int v) const { return p_.ball[k_.ball_of[v]].r; }
  void add_v_points(std::size_t s, const detail::TriplePoints& points,
                    const std::array<int, 3>& triple);

  const Prepared& p_;
  const Complex& k_;
  const Predicates pred_;
  const double unscale_;
  CompensatedSum volume_, area_;
  std::vector<int> edge_slot_, tri_slot_;  // simplex -> index in pairs_ / triples_, -1: not in K
  std::vector<detail::PairGeometry> pairs_;
  std::vector<detail::TripleGeometry> triples_;
};

void ComplexSum::add_vertices() {
  for (std::size_t s = 0; s < k_.verts.v.size(); ++s) {
    const int v = k_.verts.v[s][0];
    if (!k_.verts.in_complex[s]) {
      hidden.push_back(k_.ball_of[v]);  // its ball does not reach its power cell
      continue;
    }
    const double r = radius(v);
    add({4.0 / 3.0 * kPi * r * r * r, 4.0 * kPi * r * r}, 1);
    vertices.push_back(k_.ball_of[v]);
  }
}

void ComplexSum::add_edges() {
  edge_slot_.assign(k_.edges.v.size(), -1);
  for (std::size_t s = 0; s < k_.edges.v.size(); ++s) {
    if (!k_.edges.in_complex[s]) continue;
    const int a = k_.edges.v[s][0], b = k_.edges.v[s][1];
    edge_slot_[s] = static_cast<int>(pairs_.size());
    pairs_.push_back(detail::pair_geometry(centre(a), radius(a), centre(b), radius(b)));
    const detail::PairGeometry& g = pairs_.back();
    add(detail::pair_measure(g, radius(a), radius(b)), -1);
    edges.push_back({k_.ball_of[a], k_.ball_of[b]});
    if (!k_.edges.coface_in_complex[s]) {
      const Eigen::Vector3d u = (centre(b) - centre(a)) / g.d;
      EdgeCircle circle;
      circle.center = (centre(a) + g.a[0] * u) * unscale_;
      circle.normal = u;
      circle.radius = std::sqrt(g.rho2) * unscale_;
      circle.balls = {k_.ball_of[a], k_.ball_of[b]};
      lone_circles.push_back(circle);
    }
  }
}

void ComplexSum::add_triangles() {
  tri_slot_.assign(k_.tris.v.size(), -1);
  for (std::size_t s = 0; s < k_.tris.v.size(); ++s) {
    if (!k_.tris.in_complex[s]) continue;
    const std::array<int, 3>& t = k_.tris.v[s];
    const Eigen::Vector3d c[3] = {centre(t[0]), centre(t[1]), centre(t[2])};
    const double r[3] = {radius(t[0]), radius(t[1]), radius(t[2])};
    const detail::PairGeometry* e[3];
    for (int q = 0; q < 3; ++q) {
      const int slot = edge_slot_[k_.tris.face[s][q]];
      MEDSPHERES_ASSERT(slot >= 0);
      e[q] = &pairs_[slot];
    }
    detail::TriplePoints points;
    tri_slot_[s] = static_cast<int>(triples_.size());
    triples_.push_back(detail::triple_geometry(c, r, e, &points));
    add(detail::triple_measure(triples_.back(), r, e), 1);
    const std::array<int, 3> triple{k_.ball_of[t[0]], k_.ball_of[t[1]], k_.ball_of[t[2]]};
    triangles.push_back(triple);
    add_v_points(s, points, triple);
  }
}

// v-points of triangle s: z + t n and z - t n, unless strictly inside the ball u of a
// tetrahedron T = (t, u) of the triangulation. Let w be the position of T's power centre
// on the line z + tau n, measured towards c_u: sign(w) is the attachment test of (t, u),
// and rho_T = w^2 - t^2. On u's side of w, pi_u < pi_t. The triangle is in K, so its dual
// edge, which the regularity of the other tetrahedron bounds on the far side, reaches
// [-t, t]: w >= -t, and the point on the far side of u is never inside B_u. The point on
// u's side is inside iff t > w: iff rho_T < 0, or rho_T = 0 and w < 0 (w = -t). And
// rho_T < 0 makes the triangle's own power radius negative: two distinct points.
void ComplexSum::add_v_points(std::size_t s, const detail::TriplePoints& points,
                              const std::array<int, 3>& triple) {
  const std::array<int, 3>& t = k_.tris.v[s];
  const int dim = k_.dimension;
  bool inside[2] = {false, false};  // [0]: z + t n, [1]: z - t n
  bool may_touch = true;            // the three spheres may touch in a single point
  if (dim == 3) {
    for (const int tet : k_.tri_cofaces[s]) {
      if (tet < 0) continue;
      int q = 0;
      while (k_.tets.face[tet][q] != static_cast<int>(s)) ++q;
      const int u = k_.tets.v[tet][q];
      // orientation(t0, t1, t2, u): move u from position q to the end.
      const bool plus_side = k_.tet_orient[tet] * ((3 - q) % 2 == 0 ? 1 : -1) > 0;
      const int rho_t = k_.top_sign[tet];
      MEDSPHERES_ASSERT(rho_t <= 0 || !pred_.attaches(t, u));
      const bool covered = rho_t < 0 || (rho_t == 0 && pred_.attaches(t, u));
      inside[plus_side ? 0 : 1] = inside[plus_side ? 0 : 1] || covered;
      may_touch = may_touch && rho_t >= 0;
    }
  }
  const bool single =
      may_touch && (dim == 3 ? static_cast<int>(pred_.radius_sign(t)) : k_.top_sign[s]) == 0;
  const double tt = single ? 0.0 : triples_.back().t;
  for (int side = 0; side < (single ? 1 : 2); ++side) {
    if (inside[side]) continue;
    VPoint v;
    v.position = (points.z + (side == 0 ? tt : -tt) * points.n) * unscale_;
    v.balls = triple;
    v_points.push_back(v);
  }
}

void ComplexSum::add_tetrahedra() {
  for (std::size_t s = 0; s < k_.tets.v.size(); ++s) {
    if (!k_.tets.in_complex[s]) continue;
    const std::array<int, 4>& t = k_.tets.v[s];
    Eigen::Vector3d c[4];
    double r[4];
    for (int q = 0; q < 4; ++q) {
      c[q] = centre(t[q]);
      r[q] = radius(t[q]);
    }
    const detail::TripleGeometry* f[4];
    for (int x = 0; x < 4; ++x) {
      const int slot = tri_slot_[k_.tets.face[s][x]];
      MEDSPHERES_ASSERT(slot >= 0);
      f[x] = &triples_[slot];
    }
    const detail::PairGeometry* e[4][4] = {};
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const int x = (a != 0 && b != 0) ? 0 : (a != 1 && b != 1) ? 1 : 2;  // a face with a, b
        const int la = a - (a > x ? 1 : 0), lb = b - (b > x ? 1 : 0);
        const int slot = edge_slot_[k_.tris.face[k_.tets.face[s][x]][3 - la - lb]];
        MEDSPHERES_ASSERT(slot >= 0);
        e[a][b] = &pairs_[slot];
      }
    }
    add(detail::quadruple_measure(c, r, e, f), -1);
    tetrahedra.push_back({k_.ball_of[t[0]], k_.ball_of[t[1]], k_.ball_of[t[2]], k_.ball_of[t[3]]});
  }
}

}  // namespace

UnionOfBalls::UnionOfBalls(const std::vector<Sphere>& input) {
  check_input(input);
  if (input.empty()) return;
  Prepared p = prepare(input);
  measures_.duplicates = p.duplicates;
  std::vector<int> hidden = p.hidden;

  Clock::time_point start = Clock::now();
  Regular rt;
  triangulate(p, rt);
  seconds_.triangulation = seconds_since(start);
  start = Clock::now();
  const Complex k = classify(rt, p, hidden);
  measures_.dimension = k.dimension;
  seconds_.classification = seconds_since(start);
  start = Clock::now();

  ComplexSum sum(p, k, std::move(hidden));
  sum.add_vertices();
  sum.add_edges();
  sum.add_triangles();
  sum.add_tetrahedra();
  vertices_ = std::move(sum.vertices);
  edges_ = std::move(sum.edges);
  triangles_ = std::move(sum.triangles);
  tetrahedra_ = std::move(sum.tetrahedra);
  v_points_ = std::move(sum.v_points);
  lone_circles_ = std::move(sum.lone_circles);

  std::sort(sum.hidden.begin(), sum.hidden.end());
  measures_.hidden = std::move(sum.hidden);
  measures_.volume = sum.volume();
  measures_.area = sum.area();
  measures_.vertices = vertices_.size();
  measures_.edges = edges_.size();
  measures_.triangles = triangles_.size();
  measures_.tetrahedra = tetrahedra_.size();
  seconds_.measures = seconds_since(start);
}

UnionMeasures measure_union(const std::vector<Sphere>& balls) {
  return UnionOfBalls(balls).measures();
}

}  // namespace medspheres
