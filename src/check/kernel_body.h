// The batched kernel: forward kinematics, posed spheres and the checks of one block of
// kLanes configurations, written once over a lane type V that the including file defines
// with these functions (each lane's arithmetic is the same IEEE operations in the same
// order in every definition, so all give the same bits):
//   V splat(double); V load(const double*); void store(double*, V);
//   V operator+(V, V), operator-(V, V), operator*(V, V);
//   unsigned le_bits(V a, V b) (the lanes where a <= b, as bits).
// Included by kernel_scalar.cpp and kernel_avx2.cpp only. Everything here is internal to
// the including file (an unnamed namespace), and it calls no inline function of another
// file, so that no code built for AVX2 is shared with the scalar build.
//
// Modes (robot_checker.h): spheres only, a lane collides when a sphere of the spheres-only
// set is within the margin of an element or of a sphere of a self pair's other link;
// bounds, a pair is free when every covering sphere is farther than margin + allowance,
// colliding when an inner sphere is within margin - allowance, else undecided, level by
// level (the planner's sets, then the fine sets). Both start from the links' bounding
// spheres, farther than margin + allowance from everything: a shortcut that never changes
// an answer.

namespace medspheres::check::detail {
namespace {

// Rounds every lane to the nearest integer (ties to even), exact for |x| < 2^51.
V round_nearest(V x) {
  const double kRound = 6755399441055744.0;  // 1.5 * 2^52
  return (x + splat(kRound)) - splat(kRound);
}

// sin and cos of every lane: Cody and Waite's reduction by pi / 2 (three parts, exact for
// |x| < 2^26), Cephes' polynomials on [-pi/4, pi/4] (about 1 ulp), then the quadrant's
// swap and signs as exact arithmetic on 0, 1 and -1 (no per-lane branch).
void sincos(V x, V& s, V& c) {
  const V k = round_nearest(x * splat(0.63661977236758134308));
  const V r = ((x - k * splat(1.57079625129699707031)) - k * splat(7.54978941586159635335e-8)) -
              k * splat(5.39030285815811905290e-15);
  const V z = r * r;
  V ps = splat(1.58962301576546568060e-10);
  ps = ps * z + splat(-2.50507477628578072866e-8);
  ps = ps * z + splat(2.75573136213857245213e-6);
  ps = ps * z + splat(-1.98412698295895385996e-4);
  ps = ps * z + splat(8.33333333332211858878e-3);
  ps = ps * z + splat(-1.66666666666666307295e-1);
  V pc = splat(-1.13585365213876817300e-11);
  pc = pc * z + splat(2.08757008419747316778e-9);
  pc = pc * z + splat(-2.75573141792967388112e-7);
  pc = pc * z + splat(2.48015872888517045348e-5);
  pc = pc * z + splat(-1.38888888888730564116e-3);
  pc = pc * z + splat(4.16666666666665929218e-2);
  const V sr = r + (r * z) * ps;
  const V cr = (splat(1.0) - splat(0.5) * z) + (z * z) * pc;
  // m = k mod 4 in {0, 1, 2, 3}; sin x = (s, c, -s, -c)[m], cos x = (c, -s, -c, s)[m].
  const V m = k - splat(4.0) * round_nearest(k * splat(0.25) - splat(0.375));
  const V half = round_nearest(m * splat(0.5) - splat(0.25));               // 0, 0, 1, 1
  const V swap = m - splat(2.0) * half;                                     // 0, 1, 0, 1
  const V hc = round_nearest((m + splat(1.0)) * splat(0.5) - splat(0.25));  // 0, 1, 1, 2
  const V sign_s = splat(1.0) - splat(2.0) * half;
  const V sign_c =
      splat(1.0) - splat(2.0) * (hc - splat(2.0) * round_nearest(hc * splat(0.5) - splat(0.25)));
  const V keep = splat(1.0) - swap;
  s = (sr * keep + cr * swap) * sign_s;
  c = (cr * keep + sr * swap) * sign_c;
}

// X_WF of every moving frame (frame 0, W itself, is left as the caller set it).
void pose_frames(const KernelRobot& robot, Block& b) {
  for (int i = 0; i < robot.steps; ++i) {
    const FrameStep& s = robot.step[i];
    const V q = load(b.q + s.source * kLanes) * splat(s.multiplier) + splat(s.offset);
    V rel[12];
    if (s.prismatic) {
      for (int e = 0; e < 9; ++e) rel[e] = splat(s.P[e]);
      for (int k = 0; k < 3; ++k) rel[9 + k] = splat(s.u[k]) + q * splat(s.v[k]);
    } else {
      V sn, cs;
      sincos(q, sn, cs);
      for (int e = 0; e < 9; ++e)
        rel[e] = (splat(s.P[e]) + cs * splat(s.C[e])) + sn * splat(s.S[e]);
      for (int k = 0; k < 3; ++k) rel[9 + k] = splat(s.u[k]);
    }
    double* out = b.frames + s.frame * 12 * kLanes;
    if (s.parent == 0) {
      for (int e = 0; e < 12; ++e) store(out + e * kLanes, rel[e]);
      continue;
    }
    const double* in = b.frames + s.parent * 12 * kLanes;
    V p[12];
    for (int e = 0; e < 12; ++e) p[e] = load(in + e * kLanes);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        store(out + (3 * r + c) * kLanes,
              (p[3 * r] * rel[c] + p[3 * r + 1] * rel[3 + c]) + p[3 * r + 2] * rel[6 + c]);
      store(out + (9 + r) * kLanes,
            ((p[3 * r] * rel[9] + p[3 * r + 1] * rel[10]) + p[3 * r + 2] * rel[11]) + p[9 + r]);
    }
  }
}

// Poses the points (x, y, z)[i] of frame f into out[i * 3 * kLanes ...], i < n.
void pose_points(const Block& b, int f, const double* x, const double* y, const double* z, int n,
                 double* out) {
  const double* in = b.frames + f * 12 * kLanes;
  V R[12];
  for (int e = 0; e < 12; ++e) R[e] = load(in + e * kLanes);
  for (int i = 0; i < n; ++i) {
    const V px = splat(x[i]), py = splat(y[i]), pz = splat(z[i]);
    for (int r = 0; r < 3; ++r)
      store(out + (3 * i + r) * kLanes,
            ((R[3 * r] * px + R[3 * r + 1] * py) + R[3 * r + 2] * pz) + R[9 + r]);
  }
}

// The posed spheres of a link's set (slot < kLevels) or its bounding sphere (kBoundSlot),
// posed on first use in the block.
const double* posed(const KernelRobot& robot, Block& b, int link, int slot) {
  const LinkLayout& l = robot.link[link];
  double* out = slot == kBoundSlot ? b.posed + (robot.spheres + link) * 3 * kLanes
                                   : b.posed + l.begin[slot] * 3 * kLanes;
  unsigned char& done = b.posed_flag[link * kSlots + slot];
  if (!done) {
    if (slot == kBoundSlot)
      pose_points(b, l.frame, &l.bound[0], &l.bound[1], &l.bound[2], 1, out);
    else
      pose_points(b, l.frame, robot.x + l.begin[slot], robot.y + l.begin[slot],
                  robot.z + l.begin[slot], static_cast<int>(l.count[slot]), out);
    done = 1;
  }
  return out;
}

void lane_point(const double* posed_set, int i, int lane, double* p) {
  for (int k = 0; k < 3; ++k) p[k] = posed_set[(3 * i + k) * kLanes + lane];
}

// The grid's lower bound at p exceeds rq (so nothing is within rq of p); false outside
// the grid (the caller asks the grid itself then).
bool grid_clear(const GridView& g, const double* p, double rq) {
  if (g.lower == nullptr) return true;  // no element
  long index = 0;
  for (int k = 2; k >= 0; --k) {
    const double u = (p[k] - g.origin[k]) * g.inverse_side;
    if (!(u >= 0.0) || !(u < g.n[k])) return false;
    index = index * g.n[k] + static_cast<long>(u);
  }
  return g.lower[index] * g.unit > rq;
}

// Some sphere of the set within rq(radius) of the scene, in this lane.
bool set_within(const KernelRobot& robot, const SceneGrid& scene, const double* set, int begin,
                int count, int lane, double add) {
  double p[3];
  for (int i = 0; i < count; ++i) {
    lane_point(set, i, lane, p);
    const double rq = robot.r[begin + i] + add;
    if (!grid_clear(robot.grid, p, rq) && scene.within(p, rq)) return true;
  }
  return false;
}

// Spheres mode: a link against the scene in the lanes `need`; the lanes it collides in.
unsigned scene_spheres(const KernelRobot& robot, const SceneGrid& scene, Block& b, int link,
                       unsigned need) {
  const LinkLayout& l = robot.link[link];
  const int slot = l.spheres;
  const double* set = posed(robot, b, link, slot);
  unsigned hit = 0;
  for (int lane = 0; lane < kLanes; ++lane)
    if ((need >> lane & 1) && set_within(robot, scene, set, static_cast<int>(l.begin[slot]),
                                         static_cast<int>(l.count[slot]), lane, b.margin))
      hit |= 1u << lane;
  return hit;
}

// Bounds mode, one level (0 the planner's sets, 1 the fine ones) of a link against the
// scene in the lanes `pending`: the lanes certainly free leave `pending`, those certainly
// colliding leave it for the result.
unsigned scene_level(const KernelRobot& robot, const SceneGrid& scene, Block& b, int link,
                     int level, unsigned& pending) {
  const LinkLayout& l = robot.link[link];
  const int outer = level ? kFineOuter : kOuter, inner = level ? kFineInner : kInner;
  unsigned hit = 0;
  if (l.count[outer] > 0) {
    const double* set = posed(robot, b, link, outer);
    for (int lane = 0; lane < kLanes; ++lane)
      if ((pending >> lane & 1) &&
          !set_within(robot, scene, set, static_cast<int>(l.begin[outer]),
                      static_cast<int>(l.count[outer]), lane, b.margin + b.allowance))
        pending &= ~(1u << lane);  // certainly free
  }
  if (l.count[inner] > 0 && pending) {
    const double* set = posed(robot, b, link, inner);
    for (int lane = 0; lane < kLanes; ++lane)
      if ((pending >> lane & 1) &&
          set_within(robot, scene, set, static_cast<int>(l.begin[inner]),
                     static_cast<int>(l.count[inner]), lane, b.margin - b.allowance)) {
        hit |= 1u << lane;  // certainly colliding
        pending &= ~(1u << lane);
      }
  }
  return hit;
}

// The lanes in which some sphere of set a is within `add` + radii of some sphere of set
// b; stops when every lane of `need` is found. A sphere of a farther from b's bounding
// sphere (bound, radius rb) than that in every lane meets no sphere of b, and is skipped
// (the bounding sphere holds b's spheres with room for the rounding: the skip changes no
// answer).
unsigned sets_within(const KernelRobot& robot, const double* pa, int ba, int na, const double* pb,
                     int bb, int nb, const double* bound, double rb, double add, unsigned need) {
  unsigned hit = 0;
  const V bx = load(bound), by = load(bound + kLanes), bz = load(bound + 2 * kLanes);
  for (int i = 0; i < na; ++i) {
    const V ax = load(pa + 3 * i * kLanes), ay = load(pa + (3 * i + 1) * kLanes),
            az = load(pa + (3 * i + 2) * kLanes);
    const double ra = robot.r[ba + i] + add;
    const double cull = ra + rb + 1e-9 * (1.0 + rb);
    if (cull < 0.0) continue;
    const V ex = ax - bx, ey = ay - by, ez = az - bz;
    const unsigned open = need & ~hit & le_bits((ex * ex + ey * ey) + ez * ez, splat(cull * cull));
    if (!open) continue;
    for (int j = 0; j < nb; ++j) {
      const V dx = ax - load(pb + 3 * j * kLanes), dy = ay - load(pb + (3 * j + 1) * kLanes),
              dz = az - load(pb + (3 * j + 2) * kLanes);
      const double reach = ra + robot.r[bb + j];
      if (reach < 0.0) continue;
      hit |= le_bits((dx * dx + dy * dy) + dz * dz, splat(reach * reach));
    }
    if ((hit & need) == need) break;
  }
  return hit & need;
}

unsigned level_within(const KernelRobot& robot, Block& b, int a, int c, int slot_a, int slot_c,
                      double add, unsigned need) {
  const LinkLayout &la = robot.link[a], &lc = robot.link[c];
  return sets_within(robot, posed(robot, b, a, slot_a), static_cast<int>(la.begin[slot_a]),
                     static_cast<int>(la.count[slot_a]), posed(robot, b, c, slot_c),
                     static_cast<int>(lc.begin[slot_c]), static_cast<int>(lc.count[slot_c]),
                     posed(robot, b, c, kBoundSlot), lc.bound[3], add, need);
}

// Bounds mode, one level of a self pair in the lanes `pending`, as scene_level.
unsigned self_level(const KernelRobot& robot, Block& b, int a, int c, int level,
                    unsigned& pending) {
  const LinkLayout &la = robot.link[a], &lc = robot.link[c];
  const int outer = level ? kFineOuter : kOuter, inner = level ? kFineInner : kInner;
  if (la.count[outer] > 0 && lc.count[outer] > 0)
    pending = level_within(robot, b, a, c, outer, outer, b.margin + b.allowance, pending);
  unsigned hit = 0;
  if (la.count[inner] > 0 && lc.count[inner] > 0 && pending) {
    hit = level_within(robot, b, a, c, inner, inner, b.margin - b.allowance, pending);
    pending &= ~hit;
  }
  return hit;
}

// The lanes of `open` in which link's bounding sphere may come within the margin of the
// scene.
unsigned scene_near(const KernelRobot& robot, const SceneGrid& scene, Block& b, int link,
                    unsigned open) {
  const double* bound = posed(robot, b, link, kBoundSlot);
  const double rq = robot.link[link].bound[3] + b.margin + b.allowance;
  unsigned need = 0;
  double p[3];
  for (int lane = 0; lane < kLanes; ++lane) {
    if (!(open >> lane & 1)) continue;
    lane_point(bound, 0, lane, p);
    if (!grid_clear(robot.grid, p, rq) && !scene.clear(p, rq)) need |= 1u << lane;
  }
  return need;
}

// The lanes of `open` in which the bounding spheres of links a and c may come within the
// margin of each other.
unsigned pair_near(const KernelRobot& robot, Block& b, int a, int c, unsigned open) {
  const double* ba = posed(robot, b, a, kBoundSlot);
  const double* bc = posed(robot, b, c, kBoundSlot);
  const V dx = load(ba) - load(bc), dy = load(ba + kLanes) - load(bc + kLanes),
          dz = load(ba + 2 * kLanes) - load(bc + 2 * kLanes);
  const double reach = robot.link[a].bound[3] + robot.link[c].bound[3] + b.margin + b.allowance;
  return open & le_bits((dx * dx + dy * dy) + dz * dz, splat(reach * reach));
}

// The bounds mode level by level: every pair at the planner's level first (a certain
// collision found there spares the fine level of every other pair), then the fine level
// of the pairs still open. b.pending holds per link (scene) and per self pair the lanes
// still undecided.
unsigned run_bounds(const KernelRobot& robot, const SceneGrid& scene, Block& b) {
  unsigned char* pending = b.pending;
  for (int k = 0; k < robot.links + robot.pairs; ++k) pending[k] = 0;
  unsigned open = b.lanes;
  for (int level = 0; level < (robot.fine ? 2 : 1); ++level) {
    for (int link = 0; link < robot.links && open; ++link) {
      unsigned p = level ? pending[link] & open : scene_near(robot, scene, b, link, open);
      if (p) open &= ~scene_level(robot, scene, b, link, level, p);
      pending[link] = static_cast<unsigned char>(p);
    }
    for (int k = 0; k < robot.pairs && open && b.self; ++k) {
      const int a = static_cast<int>(robot.pair_a[k]), c = static_cast<int>(robot.pair_b[k]);
      unsigned p = level ? pending[robot.links + k] & open : pair_near(robot, b, a, c, open);
      if (p) open &= ~self_level(robot, b, a, c, level, p);
      pending[robot.links + k] = static_cast<unsigned char>(p);
    }
  }
  for (int k = 0; k < robot.links + robot.pairs; ++k) {
    const unsigned p = pending[k] & open;
    b.undecided |= p;
    for (int lane = 0; lane < kLanes && b.sink; ++lane)
      if (p >> lane & 1)
        k < robot.links ? b.sink(b, lane, k, -1)
                        : b.sink(b, lane, static_cast<int>(robot.pair_a[k - robot.links]),
                                 static_cast<int>(robot.pair_b[k - robot.links]));
  }
  return open;
}

// The spheres mode: every link against the scene, then every self pair.
unsigned run_spheres(const KernelRobot& robot, const SceneGrid& scene, Block& b) {
  unsigned open = b.lanes;
  for (int link = 0; link < robot.links && open; ++link) {
    const unsigned need = scene_near(robot, scene, b, link, open);
    if (need) open &= ~scene_spheres(robot, scene, b, link, need);
  }
  for (int k = 0; k < robot.pairs && open && b.self; ++k) {
    const int a = static_cast<int>(robot.pair_a[k]), c = static_cast<int>(robot.pair_b[k]);
    const unsigned need = pair_near(robot, b, a, c, open);
    const LinkLayout &la = robot.link[a], &lc = robot.link[c];
    if (need) open &= ~level_within(robot, b, a, c, la.spheres, lc.spheres, b.margin, need);
  }
  return open;
}

void run_block(const KernelRobot& robot, const SceneGrid& scene, Block& b) {
  for (int k = 0; k < robot.links * kSlots; ++k) b.posed_flag[k] = 0;
  b.colliding = b.undecided = 0;
  pose_frames(robot, b);
  const unsigned open = b.bounds ? run_bounds(robot, scene, b) : run_spheres(robot, scene, b);
  b.colliding = b.lanes & ~open;
  b.undecided &= ~b.colliding;
}

}  // namespace
}  // namespace medspheres::check::detail
