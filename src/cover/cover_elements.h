#pragma once
// Private to the covering bake (cover.cpp): what a cover must hold (the elements), the
// clustering that holds them (balls, and the ball that owns each element), and the
// operations on both that every stage uses. Derivations in cover_elements.cpp.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "medspheres/mesh/mesh_query.h"
#include "medspheres/scalar_distance.h"
#include "medspheres/sphere_set.h"

namespace medspheres::detail {

// The deepest midpoint subdivision of a mesh triangle into elements; the certificate must
// be allowed at least this depth.
constexpr int kMaxElementDepth = 5;

// Constraint points and the elements made of them: elements [0, surface) are surface
// pieces, the rest interior points (one index, four times). A piece is a triangle (a, b,
// c, c) or, on a mesh of more triangles than the bake needs, two mesh triangles that share
// the edge ab (a, b, c, d: the triangles abc and abd; a ball holding the four corners holds
// both). Each element's weight is the area it stands for (a piece: its own; an interior
// point: the square of the interior grid's cell). Patches are elements too, without points:
// each is the ball (centroid, reach) that holds the points of the elements it stands for,
// and weighs what they weigh.
struct Elements {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 4>> items;  // empty for patches
  std::vector<Eigen::Vector3d> centroids;
  std::vector<double> reach;  // largest centroid-corner distance
  std::vector<double> weight;
  std::size_t surface = 0;
  double element_size = 0.0;  // the surface elements' target length
  bool paired = false;        // the mesh's triangles went in pairs (make_elements)
  bool patches() const { return items.empty(); }
  std::size_t size() const { return centroids.size(); }
};

// The surface elements for a budget and a grid of interior points (\p interior_resolution
// cells along L; 0: none), inside where the winding number exceeds 1/2.
Elements make_elements(const MeshQuery& query, std::size_t budget, int interior_resolution,
                       int threads);

// The surface elements grouped into at most about max(floor, 60 budget) patches by the
// cells of a grid over the box from \p origin; interior points stay patches of their own.
Elements make_patches(const Elements& e, std::size_t budget, double floor,
                      const Eigen::Vector3d& origin);

// The distance from c to the farthest point of element i (of its ball, for a patch).
// Inline: the bake's inner loops call it millions of times.
inline double farthest(const Elements& e, std::size_t i, const Eigen::Vector3d& c) {
  if (e.patches()) return distance(e.centroids[i], c) + e.reach[i];
  // The largest squared distance, then one root: the same value as the largest root (the
  // root is correctly rounded and monotone).
  double m = 0.0;
  for (int p : e.items[i])
    m = std::max(m, squared_distance(e.points[static_cast<std::size_t>(p)], c));
  return std::sqrt(m);
}
// Whether surface element i is two mesh triangles (a, b, c, d).
inline bool paired(const Elements& e, std::size_t i) {
  return e.items[i][3] != e.items[i][2];
}
// The growth ball b needs to hold element i.
double need(const Elements& e, std::size_t i, const Sphere& b);
// Whether ball b holds element i.
inline bool holds(const Elements& e, std::size_t i, const Sphere& b) {
  const double reach = b.radius + e.reach[i];
  if (squared_distance(e.centroids[i], b.center) > reach * reach) return false;
  return farthest(e, i, b.center) <= b.radius;
}

// What a ball must hold to hold the elements in \p members, into \p atoms (cleared first):
// their distinct points (balls of radius 0), or for patches their balls. \p mark: scratch,
// one per point, all 0. A caller's loop reuses \p atoms: fresh lists of this size cost a
// page fault per page, most of the sanitizer builds' bake time.
void atoms_into(const Elements& e, const std::vector<std::size_t>& members, std::vector<char>& mark,
                std::vector<Sphere>& atoms);
// The radius that a ball centred at c needs to hold \p atoms.
double reach_from(const std::vector<Sphere>& atoms, const Eigen::Vector3d& c);
// A reach (a largest distance, rounded) raised by 4 ulps: a radius that the rounding of the
// distances never leaves short of what it must hold.
inline double raised(double reach) {
  return reach * (1.0 + 4.0 * std::numeric_limits<double>::epsilon());
}
// raised(reach_from(atoms, c)).
double holding_radius(const std::vector<Sphere>& atoms, const Eigen::Vector3d& c);
// reach_from(atoms, y) for points y near a pivot x0, exactly, from a subset: an atom with
// |a - x0| + r_a < R(x0) - 2 delta (R the reach at x0) is nearer than R - delta to any y
// within delta of x0, while the atom farthest from x0 is at least that far from y; so
// only the others are scanned. The pivot moves (a full scan) when y leaves its delta
// ball or the asked delta falls below an eighth of the pivot's. \p atoms and the buffer
// must outlive it.
class FarthestAtoms {
 public:
  // The subset is kept in \p buffer (cleared), whose memory a caller's loop reuses.
  FarthestAtoms(const std::vector<Sphere>& atoms, std::vector<Sphere>& buffer)
      : atoms_(atoms), near_(buffer) {
    near_.clear();
  }
  FarthestAtoms(const FarthestAtoms&) = delete;
  FarthestAtoms& operator=(const FarthestAtoms&) = delete;
  double operator()(const Eigen::Vector3d& y, double delta) {
    return reach_from(near(y, delta), y);
  }
  // The subset that gives reach_from(atoms, z) for every z within delta of y.
  const std::vector<Sphere>& near(const Eigen::Vector3d& y, double delta) {
    if (near_.empty() || delta > delta_ || 8.0 * delta < delta_ || (y - pivot_).norm() > delta_)
      pivot(y, delta);
    return near_;
  }

 private:
  void pivot(const Eigen::Vector3d& x, double delta);
  const std::vector<Sphere>& atoms_;
  std::vector<Sphere>& near_;
  Eigen::Vector3d pivot_ = Eigen::Vector3d::Zero();
  double delta_ = 0.0;
};
// The minimum enclosing ball of the points of the elements in \p members.
Sphere fit(const Elements& e, const std::vector<std::size_t>& members, std::vector<char>& mark);

// The exact volume of the union of the balls of radius > 0.
double union_volume(const std::vector<Sphere>& balls);

struct Clustering {
  std::vector<Sphere> balls;
  std::vector<int> owner;  // per element, the ball that holds it
  // Per element, the last shrink's marks (1: no ball other than its owner held it), valid
  // while the balls and owners are as that shrink left them (drop_empty keeps them); every
  // step that moves or grows a ball or reassigns an element clears them (empty: none), and
  // refine_binding uses them.
  std::vector<char> settled;
};

std::vector<std::vector<std::size_t>> members_of(const std::vector<int>& owner, std::size_t k);

// Each element to the centre whose farthest point of the element is nearest, or with
// \p depth (one per ball) whose protrusion to hold it, that distance minus depth, is least
// (ties: lowest index).
void assign(const Elements& e, const std::vector<Sphere>& balls, std::vector<int>& owner,
            int threads, const std::vector<double>& depth = {});
// Each ball, its centre kept, just large enough for the elements it owns (0: none).
void hold_members(const Elements& e, Clustering& c);
// Each element to the ball that must grow least to hold it, then hold_members.
void hold_all(const Elements& e, Clustering& c, int threads);
// Each ball gives up the elements another ball holds and shrinks to what it keeps; a ball
// left with nothing gets radius 0. Every element stays held. Leaves its marks in
// c.settled. With \p refining it starts from them (when there is one per element), so an
// element marked is not checked again, and an element that another ball holds but that lies
// well within what its own ball keeps (2 reaches inside) stays: moving it would shrink
// neither ball, only hand it back and forth between passes.
void shrink(const Elements& e, Clustering& c, bool refining = false);
// The surface elements that bind a ball's radius split in four, then shrink, \p levels
// times: the balls shrink to where the others' reach ends, at a finer grain than the
// elements'. \p e gains the split elements. Every element stays held.
void refine_binding(Elements& e, Clustering& c, int levels);
// The balls of radius > 0 only, the owners renumbered.
void drop_empty(Clustering& c);

// The signed distance to the surface (positive inside) at y, near a point x whose own
// value px is known: the closest-point search starts from x's triangle, and when |y - x|
// < |px.depth| the segment xy does not meet the surface, so y is on x's side and no
// winding number is needed. An empty px (triangle -1) asks the winding number.
struct Probe {
  double depth = 0.0;
  int triangle = -1;
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();  // the nearest point of the surface
};
Probe probe(const MeshQuery& query, const Eigen::Vector3d& y, const Eigen::Vector3d& x,
            const Probe& px);
// An upper bound on the signed distance that probe(query, y, x, px) returns, without a
// closest-point query: the distance from y to px's triangle (D(y) <= |D(y)| <= it) plus a
// margin above the rounding of both; +infinity when px has no triangle of the mesh (none, or
// a cap's). A search for a deeper point skips y when even this depth does not help.
double depth_bound(const MeshQuery& query, const Eigen::Vector3d& y, const Probe& px);

}  // namespace medspheres::detail
