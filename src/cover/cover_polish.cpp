// The volume polish of the covering bake (cover_polish.h).
//
// The volume stage's flow moves all balls at once on a penalty: its balls hold the elements
// only nearly, its gradient of the union's volume is sampled on a lattice of directions,
// and the step that makes it hold every element again (each element to the ball that must
// grow least) leaves the balls where the flow put them. The polish is exact where the flow
// is not: it moves one ball at a time, on the exact volume of the union, with the ball's
// elements held exactly and its protrusion within the cap, and keeps only moves that lower
// the union.
//
// Pattern search. For ball j with centre x and elements M_j: steps of length h from x along
// the six axes and the eight diagonals (h from kFirst r_j, halved when none helps, down to
// kLast r_j; the direction that helped last is tried first); at y the radius is
// holding_radius(M_j, y), and y is taken when the protrusion there (radius minus the signed
// distance of y) is at most the cap and the union's volume falls. (With the six axes alone
// the right ankle pitch link of the G1 at K = 8 kept 3% more excess volume.)
//
// Only ball j changes, so the change of the union's volume is the change of the part of j
// outside the others: vol(B \ O) = vol(B u N) - vol(N), N the balls that meet B (exact
// volumes, union_volume.h). The old and the new ball are each measured with the balls
// that meet them; a move is kept when it lowers that part by more than kGain of the
// union's volume (far above the measures' rounding, a few eps of it).
//
// Balls whose searches cannot meet run at once: a centre moves at most kTravel r_j in a
// sweep, so the ball stays in (c_j, (1 + 2 kTravel) r_j), and balls whose such regions are
// apart neither read nor move anything the other's search depends on. The classes are made
// greedily in index order, so the result is the same for every thread count.
//
// Then shrink: an element that another ball now holds is handed to it, and every ball
// shrinks to what it keeps, which lowers the union again and gives the next sweep's
// searches room (without it between sweeps, the right ankle pitch link kept 2.4% more
// excess volume). Only the elements that a moved ball may now hold are checked again.
#include "cover_polish.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <omp.h>

namespace medspheres::detail {

namespace {

constexpr double kFirst = 0.1, kLast = 1e-3;  // the search's steps, relative to the radius
constexpr double kTravel = 0.5;      // how far a centre moves in one sweep, relative to its radius
constexpr double kGain = 1e-9;       // least gain kept, relative to the union
constexpr double kSweepGain = 1e-3;  // a sweep gaining less (relative) ends the polish
// Each ball's search stops once its measures of the union have taken kWork / K balls in all
// (K balls), so that a sweep's measures cost about the same at every budget (the first sweep
// on the G1's head link at K = 29 took 17,500 without the bound).
constexpr std::size_t kWork = 24000;

// The six axes and the eight diagonals, unit length.
const std::array<Eigen::Vector3d, 14>& directions() {
  static const std::array<Eigen::Vector3d, 14> d = [] {
    std::array<Eigen::Vector3d, 14> out;
    std::size_t k = 0;
    for (int a = 0; a < 3; ++a)
      out[k++] = Eigen::Vector3d::Unit(a), out[k++] = -Eigen::Vector3d::Unit(a);
    for (int sx : {-1, 1})
      for (int sy : {-1, 1})
        for (int sz : {-1, 1}) out[k++] = Eigen::Vector3d(sx, sy, sz).normalized();
    return out;
  }();
  return d;
}

// The volume of a ball outside the balls of \p balls other than j (exact), with the volume
// of the others that meet it kept for the next call: while the ball moves a little, the
// same others meet it.
class OutsideOthers {
 public:
  OutsideOthers(const std::vector<Sphere>& balls, std::size_t j) : balls_(balls), j_(j) {}
  double operator()(const Sphere& b) {
    std::vector<std::size_t> near;
    for (std::size_t o = 0; o < balls_.size(); ++o) {
      const double reach = b.radius + balls_[o].radius;
      if (o != j_ && balls_[o].radius > 0.0 &&
          (balls_[o].center - b.center).squaredNorm() < reach * reach)
        near.push_back(o);
    }
    if (near.empty()) return 4.0 / 3.0 * M_PI * b.radius * b.radius * b.radius;
    std::vector<Sphere> s;
    for (std::size_t o : near) s.push_back(balls_[o]);
    if (near != near_) near_ = near, without_ = union_volume(s), work_ += s.size();
    s.push_back(b);
    work_ += s.size();
    return union_volume(s) - without_;
  }
  // The balls measured so far, over all unions: the search's cost.
  std::size_t work() const { return work_; }

 private:
  const std::vector<Sphere>& balls_;
  std::size_t j_;
  std::vector<std::size_t> near_;
  double without_ = 0.0;
  std::size_t work_ = 0;
};

// The pattern search (file comment) on ball j of \p balls, with \p atoms what it must
// hold. \p balls is only read. Returns the ball found.
// \p near: scratch for the atoms that may be farthest (FarthestAtoms).
Sphere search_ball(const MeshQuery& query, const std::vector<Sphere>& balls, std::size_t j,
                   const std::vector<Sphere>& atoms, std::vector<Sphere>& near, double cap,
                   double least_gain, std::size_t work) {
  Sphere ball = balls[j];
  const Eigen::Vector3d x0 = ball.center;
  Eigen::Vector3d x = x0;
  Probe px = probe(query, x, x, {});
  OutsideOthers outside(balls, j);
  double part = outside(ball);
  const double r0 = ball.radius;
  FarthestAtoms reach(atoms, near);
  const auto& dirs = directions();
  std::size_t last = 0;  // the direction that helped last, tried first
  for (double step = kFirst * r0; step > kLast * r0 && outside.work() < work;) {
    bool moved = false;
    for (std::size_t k = 0; k < dirs.size() && !moved && outside.work() < work; ++k) {
      const std::size_t axis = (last + k) % dirs.size();
      const Eigen::Vector3d y = x + step * dirs[axis];
      if ((y - x0).norm() > kTravel * r0) continue;
      // holding_radius(atoms, y), from the atoms that may be farthest from y.
      const double r = raised(reach(y, 4.0 * step));
      // The protrusion falls as the depth grows: at the depth's upper bound it is a lower
      // bound.
      if (r - depth_bound(query, y, px) > cap) continue;
      const Probe py = probe(query, y, x, px);
      if (r - py.depth > cap) continue;
      const Sphere there_ball{y, r};
      const double there = outside(there_ball);
      if (!(there < part - least_gain)) continue;
      x = y, px = py, part = there, moved = true, last = axis;
      ball = there_ball;
    }
    if (!moved) step *= 0.5;
  }
  return ball;
}

// Classes of the balls in \p active whose search regions are apart (file comment),
// greedily in index order.
std::vector<std::vector<std::size_t>> apart_classes(const std::vector<Sphere>& balls,
                                                    const std::vector<char>& active) {
  std::vector<std::vector<std::size_t>> classes;
  const double grow = 1.0 + 2.0 * kTravel;
  for (std::size_t j = 0; j < balls.size(); ++j) {
    if (!active[j] || !(balls[j].radius > 0.0)) continue;
    std::size_t k = 0;
    for (; k < classes.size(); ++k) {
      bool apart = true;
      for (std::size_t o : classes[k]) {
        const double reach = grow * (balls[j].radius + balls[o].radius);
        if ((balls[j].center - balls[o].center).squaredNorm() < reach * reach) {
          apart = false;
          break;
        }
      }
      if (apart) break;
    }
    if (k == classes.size()) classes.emplace_back();
    classes[k].push_back(j);
  }
  return classes;
}

// Whether balls a and b meet (their interiors overlap).
bool meet(const Sphere& a, const Sphere& b) {
  const double reach = a.radius + b.radius;
  return (a.center - b.center).squaredNorm() < reach * reach;
}

// After the first sweep, a ball is searched again only when it or a ball that meets it
// changed in the sweep before: otherwise its search would find what it found then.
std::vector<char> changed_near(const std::vector<Sphere>& before,
                               const std::vector<Sphere>& after) {
  std::vector<char> active(after.size(), 1);
  if (before.size() != after.size()) return active;
  std::vector<char> changed(after.size(), 0);
  for (std::size_t j = 0; j < after.size(); ++j)
    changed[j] = before[j].center != after[j].center || before[j].radius != after[j].radius;
  for (std::size_t j = 0; j < after.size(); ++j) {
    active[j] = changed[j];
    for (std::size_t o = 0; o < after.size() && !active[j]; ++o)
      active[j] = changed[o] && (meet(after[j], after[o]) || meet(after[j], before[o]));
  }
  return active;
}

// The shrink's marks (cover_elements.h) of the elements that a ball changed since \p before
// may now hold, cleared: the others are still held by no ball but their owner (a ball
// that holds an element holds its centroid).
void unsettle_near_changes(const Elements& e, const std::vector<Sphere>& before, Clustering& c) {
  for (std::size_t o = 0; o < c.balls.size(); ++o) {
    const Sphere& b = c.balls[o];
    if (b.center == before[o].center && b.radius == before[o].radius) continue;
    for (std::size_t i = 0; i < e.size(); ++i)
      if (c.settled[i] && c.owner[i] != static_cast<int>(o) &&
          (e.centroids[i] - b.center).squaredNorm() <= b.radius * b.radius)
        c.settled[i] = 0;
  }
}

// A thread's scratch for the searches: the point marks (all 0 between uses) and the atom
// lists, kept over every sweep, since fresh lists cost a page fault per page.
struct SearchScratch {
  std::vector<char> mark;
  std::vector<Sphere> atoms, near;
};

// One sweep over the balls in \p active (file comment), in classes of balls apart: a
// class's balls are searched in parallel against the balls as the classes before left
// them. One thread team for the sweep; \p scratch: one per thread of \p threads.
void sweep_balls(const MeshQuery& query, const Elements& e, Clustering& c, double cap,
                 const std::vector<char>& active, double least_gain, int threads,
                 std::vector<SearchScratch>& scratch) {
  const auto members = members_of(c.owner, c.balls.size());
  const std::size_t work = kWork / std::max<std::size_t>(c.balls.size(), 1);
  const std::vector<std::vector<std::size_t>> classes = apart_classes(c.balls, active);
  std::vector<Sphere> found(c.balls.size());
#pragma omp parallel num_threads(threads)
  {
    // References, not a structured binding: clang's OpenMP cannot capture one (C++17).
    SearchScratch& mine = scratch[static_cast<std::size_t>(omp_get_thread_num())];
    std::vector<char>& mark = mine.mark;
    std::vector<Sphere>& atoms = mine.atoms;
    std::vector<Sphere>& near = mine.near;
    mark.resize(e.points.size(), 0);
    for (const std::vector<std::size_t>& group : classes) {
      const long long n = static_cast<long long>(group.size());
#pragma omp for schedule(dynamic, 1)
      for (long long g = 0; g < n; ++g) {
        const std::size_t j = group[static_cast<std::size_t>(g)];
        if (members[j].empty()) {
          found[j] = c.balls[j];
          continue;
        }
        atoms_into(e, members[j], mark, atoms);
        found[j] = search_ball(query, c.balls, j, atoms, near, cap, least_gain, work);
      }
#pragma omp single
      for (std::size_t j : group) c.balls[j] = found[j];
    }
  }
}

}  // namespace

Clustering volume_polish(const MeshQuery& query, const Elements& e, Clustering c, double cap,
                         int sweeps, int threads) {
  drop_empty(c);
  if (c.settled.size() != e.size()) c.settled.assign(e.size(), 0);
  std::vector<char> active(c.balls.size(), 1);
  std::vector<SearchScratch> scratch(static_cast<std::size_t>(std::max(threads, 1)));
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    const std::vector<Sphere> start = c.balls;
    const double before = union_volume(c.balls);
    sweep_balls(query, e, c, cap, active, kGain * before, threads, scratch);
    unsettle_near_changes(e, start, c);
    shrink(e, c, true);
    drop_empty(c);
    if (!(union_volume(c.balls) < (1.0 - kSweepGain) * before)) break;
    active = changed_near(start, c.balls);
  }
  return c;
}

}  // namespace medspheres::detail
