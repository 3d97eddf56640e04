// The batched kernel: forward kinematics, posed spheres and the checks of one block of
// kLanes configurations, written once over lane types that the including file defines
// (each lane's arithmetic is the same IEEE operations in the same order in every
// definition, so all give the same bits):
//   VD: kHalf doubles, VF: kLanes floats, each with `using T` (the scalar) and `W` (lanes);
//   V splat(T); V load(const T*); void store(T*, V); V operator+, -, * (V, V);
//   unsigned le_bits(V a, V b) (the lanes where a <= b, as bits);
//   VF to_float(VD lo, VD hi) (lanes 0-3 from lo, 4-7 from hi, each rounded to nearest);
//   V vmax(V a, V b) (a > b ? a : b per lane);
//   V gather_cells(const GridView<T>& g, V ux, V uy, V uz, unsigned inside, V& cx, V& cy,
//     V& cz, V& upper) (in the lanes `inside`, the cell (i, j, k) = ((int)ux, (int)uy,
//     (int)uz) of the field: its lower byte (returned) and upper byte, and i, j, k in cx,
//     cy, cz; 0 in the other lanes);
//   void truncate_cells(VD x, unsigned in, uint32_t* out) (out[l] = (uint32_t)x[l] in the
//     lanes `in`, each within [0, 2^16), else 0);
//   unsigned table_bits(const PairTableView& t, const uint32_t* fine) (per lane l of kLanes,
//     bit c of t.bits, c = sum over j < t.sources of (fine[t.slot[j] * kLanes + l] >>
//     t.shift[j]) * t.stride[j], each fine index < 2^16).
// Included by kernel_scalar.cpp and kernel_avx2.cpp only. Everything here is internal to
// the including file (an unnamed namespace), and it calls no inline function of another
// file but float_sincos.h's template, instantiated on this file's own lane types (so
// internal to it too): no code built for AVX2 is shared with the scalar build.
//
// Modes (robot_checker.h): spheres only, a lane collides when a sphere of the spheres-only
// set is within the margin of an element or of a sphere of a self pair's other link;
// bounds, a pair is free when every covering sphere is farther than margin + allowance,
// colliding when an inner sphere is within margin - allowance, else undecided, level by
// level (the planner's sets, then the fine sets). Both start from the links' bounding
// spheres, farther than margin + allowance from everything: a shortcut that never changes
// an answer.
//
// Precision: the float pass poses the frames in floats (each revolute joint's angle
// reduced in doubles, its sine, cosine and transform in floats, the chain's products in
// floats) and runs every test on them with `slack` (robot_checker.cpp's float_slack:
// more than any float posed point's distance from its double twin, which grows with the
// chain's depth, plus the float tests' own rounding): a test is certain when its float
// value clears its threshold by the slack, unsure otherwise. A lane whose verdict rests
// on an unsure test is checked again by the double pass (the frames of its half posed in
// doubles, slack 0: the documented tests, exactly), so every verdict is the double one.

#include "float_sincos.h"

namespace medspheres::check::detail {
namespace {

// The small helpers of the hot loops, inlined into their callers whatever the compiler's
// size heuristics say: a call of an AVX2 function costs a vzeroupper and a stack frame
// each time, which in the spheres mode took more time than the helpers' own arithmetic.
#define MEDSPHERES_KERNEL_INLINE inline __attribute__((always_inline))

// ---- Forward kinematics, in doubles, kHalf lanes at a time.

// Rounds every lane to the nearest integer (ties to even), exact for |x| < 2^51 (doubles)
// or 2^22 (floats).
template <class V>
MEDSPHERES_KERNEL_INLINE V round_nearest(V x) {
  using T = typename V::T;
  const T kRound = sizeof(T) == sizeof(double) ? T(6755399441055744.0) : T(12582912.0);  // 1.5 2^p
  return (x + splat(kRound)) - splat(kRound);
}

// x reduced by pi / 2 (Cody and Waite's reduction, three parts, exact for |x| < 2^26):
// r in [-pi/4, pi/4] (a hair more: the quotient's rounding), and the quadrant m = k mod 4
// in {0, 1, 2, 3} of the quotient k.
MEDSPHERES_KERNEL_INLINE void reduce_angle(VD x, VD& r, VD& m) {
  const VD k = round_nearest(x * splat(0.63661977236758134308));
  r = ((x - k * splat(1.57079625129699707031)) - k * splat(7.54978941586159635335e-8)) -
      k * splat(5.39030285815811905290e-15);
  m = k - splat(4.0) * round_nearest(k * splat(0.25) - splat(0.375));
}

// The quadrant m's selectors, each 0, 1 or -1: sin x = (sin r keep + cos r swap) sign_s,
// cos x = (cos r keep + sin r swap) sign_c, as sin x = (s, c, -s, -c)[m] and cos x = (c,
// -s, -c, s)[m]; exact arithmetic on small integers (no per-lane branch), so the same
// values in doubles and in floats.
template <class V>
MEDSPHERES_KERNEL_INLINE void quadrant(V m, V& keep, V& swap, V& sign_s, V& sign_c) {
  using T = typename V::T;
  const V one = splat(T(1)), two = splat(T(2)), half_ = splat(T(0.5)), quarter = splat(T(0.25));
  const V half = round_nearest(m * half_ - quarter);        // 0, 0, 1, 1
  swap = m - two * half;                                    // 0, 1, 0, 1
  const V hc = round_nearest((m + one) * half_ - quarter);  // 0, 1, 1, 2
  sign_s = one - two * half;
  sign_c = one - two * (hc - two * round_nearest(hc * half_ - quarter));
  keep = one - swap;
}

// sin and cos of every lane: reduce_angle, then Cephes' polynomials on [-pi/4, pi/4]
// (about 1 ulp).
MEDSPHERES_KERNEL_INLINE void sincos(VD x, VD& s, VD& c) {
  VD r, m, keep, swap, sign_s, sign_c;
  reduce_angle(x, r, m);
  quadrant(m, keep, swap, sign_s, sign_c);
  const VD z = r * r;
  VD ps = splat(1.58962301576546568060e-10);
  ps = ps * z + splat(-2.50507477628578072866e-8);
  ps = ps * z + splat(2.75573136213857245213e-6);
  ps = ps * z + splat(-1.98412698295895385996e-4);
  ps = ps * z + splat(8.33333333332211858878e-3);
  ps = ps * z + splat(-1.66666666666666307295e-1);
  VD pc = splat(-1.13585365213876817300e-11);
  pc = pc * z + splat(2.08757008419747316778e-9);
  pc = pc * z + splat(-2.75573141792967388112e-7);
  pc = pc * z + splat(2.48015872888517045348e-5);
  pc = pc * z + splat(-1.38888888888730564116e-3);
  pc = pc * z + splat(4.16666666666665929218e-2);
  const VD sr = r + (r * z) * ps;
  const VD cr = (splat(1.0) - splat(0.5) * z) + (z * z) * pc;
  s = (sr * keep + cr * swap) * sign_s;
  c = (cr * keep + sr * swap) * sign_c;
}

// The transform X_PF of step s for the lanes of half h, in doubles: rows of R, then p.
MEDSPHERES_KERNEL_INLINE void step_transform(const FrameStep& s, const Block& b, int h,
                                             VD rel[12]) {
  const VD q = load(b.q + s.source * kLanes + h * kHalf) * splat(s.multiplier) + splat(s.offset);
  if (s.prismatic) {
    for (int e = 0; e < 9; ++e) rel[e] = splat(s.P[e]);
    for (int k = 0; k < 3; ++k) rel[9 + k] = splat(s.u[k]) + q * splat(s.v[k]);
    return;
  }
  VD sn, cs;
  sincos(q, sn, cs);
  for (int e = 0; e < 9; ++e) rel[e] = (splat(s.P[e]) + cs * splat(s.C[e])) + sn * splat(s.S[e]);
  for (int k = 0; k < 3; ++k) rel[9 + k] = splat(s.u[k]);
}

// out = X_WP rel (frames of V::W lanes, stored as 12 rows of W), or rel when the parent
// is W itself.
template <class V>
MEDSPHERES_KERNEL_INLINE void compose(const typename V::T* in, bool parent_is_world,
                                      const V rel[12], typename V::T* out) {
  constexpr int W = V::W;
  if (parent_is_world) {
    for (int e = 0; e < 12; ++e) store(out + e * W, rel[e]);
    return;
  }
  V p[12];
  for (int e = 0; e < 12; ++e) p[e] = load(in + e * W);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      store(out + (3 * r + c) * W,
            (p[3 * r] * rel[c] + p[3 * r + 1] * rel[3 + c]) + p[3 * r + 2] * rel[6 + c]);
    store(out + (9 + r) * W,
          ((p[3 * r] * rel[9] + p[3 * r + 1] * rel[10]) + p[3 * r + 2] * rel[11]) + p[9 + r]);
  }
}

// X_WF of every moving frame for the lanes of half h, in doubles (frame 0, W itself, is
// left as the caller set it).
void pose_frames(const KernelRobot& robot, const Block& b, int h) {
  double* frames = b.frames + h * robot.frames * 12 * kHalf;
  for (int i = 0; i < robot.steps; ++i) {
    const FrameStep& s = robot.step[i];
    VD rel[12];
    step_transform(s, b, h, rel);
    compose<VD>(frames + s.parent * 12 * kHalf, s.parent == 0, rel, frames + s.frame * 12 * kHalf);
  }
}

// The transform X_PF of step s for all kLanes lanes, in floats. Revolute: the angle in
// doubles and reduced by reduce_angle as sincos does (the same r and quadrant; the
// quadrant's selectors in floats, the same values), r rounded to floats, its sine and
// cosine by float_sincos_reduced (within kFloatSinCosError of the double ones' r), then
// R = P + cos C + sin S in floats from the constants rounded to floats. Prismatic:
// step_transform's doubles, rounded.
MEDSPHERES_KERNEL_INLINE void step_transform_float(const FrameStep& s, const Block& b, VF rel[12]) {
  if (s.prismatic) {
    VD lo[12], hi[12];
    step_transform(s, b, 0, lo);
    step_transform(s, b, 1, hi);
    for (int e = 0; e < 12; ++e) rel[e] = to_float(lo[e], hi[e]);
    return;
  }
  VD r[2], m[2];
  for (int h = 0; h < 2; ++h) {
    const VD q = load(b.q + s.source * kLanes + h * kHalf) * splat(s.multiplier) + splat(s.offset);
    reduce_angle(q, r[h], m[h]);
  }
  VF sr, cr, keep, swap, sign_s, sign_c;
  float_sincos_reduced(to_float(r[0], r[1]), sr, cr, [](float x) { return splat(x); });
  quadrant(to_float(m[0], m[1]), keep, swap, sign_s, sign_c);
  const VF sn = (sr * keep + cr * swap) * sign_s;
  const VF cs = (cr * keep + sr * swap) * sign_c;
  for (int e = 0; e < 9; ++e) rel[e] = (splat(s.Pf[e]) + cs * splat(s.Cf[e])) + sn * splat(s.Sf[e]);
  for (int k = 0; k < 3; ++k) rel[9 + k] = splat(s.uf[k]);
}

// X_WF of every moving frame for all kLanes lanes, in floats: each step's transform by
// step_transform_float, then the chain's products in floats. Their distance from the
// double frames grows with the chain's depth; the float tests' slack covers it
// (robot_checker.cpp, float_slack).
void pose_frames_float(const KernelRobot& robot, const Block& b) {
  for (int i = 0; i < robot.steps; ++i) {
    const FrameStep& s = robot.step[i];
    VF rel[12];
    step_transform_float(s, b, rel);
    compose<VF>(b.frames_f + s.parent * 12 * kLanes, s.parent == 0, rel,
                b.frames_f + s.frame * 12 * kLanes);
  }
}

// ---- The tests, in either precision (V: VD or VF).

// What a pass needs besides the block: the robot's spheres in its precision.
template <class V>
struct Ctx {
  using T = typename V::T;
  static constexpr int W = V::W;
  const KernelRobot& robot;
  const KernelSpheres<T>& sp;
  const SceneGrid& scene;
  Block& b;
  Pass<T>& p;
};

// Poses the points (x, y, z)[i] of frame f into out[i * 3 * W ...], i < n.
template <class V>
MEDSPHERES_KERNEL_INLINE void pose_points(const typename V::T* frames, int f,
                                          const typename V::T* x, const typename V::T* y,
                                          const typename V::T* z, int n, typename V::T* out) {
  constexpr int W = V::W;
  const typename V::T* in = frames + f * 12 * W;
  V R[12];
  for (int e = 0; e < 12; ++e) R[e] = load(in + e * W);
  for (int i = 0; i < n; ++i) {
    const V px = splat(x[i]), py = splat(y[i]), pz = splat(z[i]);
    for (int r = 0; r < 3; ++r)
      store(out + (3 * i + r) * W,
            ((R[3 * r] * px + R[3 * r + 1] * py) + R[3 * r + 2] * pz) + R[9 + r]);
  }
}

// The posed spheres of a link's set (slot < kLevels) or its bounding sphere (kBoundSlot),
// posed on first use in the pass.
template <class V>
MEDSPHERES_KERNEL_INLINE const typename V::T* posed(const Ctx<V>& c, int link, int slot) {
  constexpr int W = V::W;
  const LinkLayout& l = c.robot.link[link];
  typename V::T* out = slot == kBoundSlot ? c.p.posed + (c.robot.spheres + link) * 3 * W
                                          : c.p.posed + l.begin[slot] * 3 * W;
  unsigned char& done = c.p.posed_flag[link * kSlots + slot];
  if (!done) {
    const auto* bound = c.sp.bound + 4 * link;
    if (slot == kBoundSlot)
      pose_points<V>(c.p.frames, l.frame, bound, bound + 1, bound + 2, 1, out);
    else
      pose_points<V>(c.p.frames, l.frame, c.sp.x + l.begin[slot], c.sp.y + l.begin[slot],
                     c.sp.z + l.begin[slot], static_cast<int>(l.count[slot]), out);
    done = 1;
  }
  return out;
}

template <class V>
MEDSPHERES_KERNEL_INLINE void lane_point(const typename V::T* posed_set, int i, int lane,
                                         double* p) {
  for (int k = 0; k < 3; ++k) p[k] = double(posed_set[(3 * i + k) * V::W + lane]);
}

// The point (x, y, z) in cell units of the field (ux, uy, uz); returns the lanes inside it
// (0 <= u < n on every axis).
template <class V>
MEDSPHERES_KERNEL_INLINE unsigned grid_cell(const GridView<typename V::T>& g, V x, V y, V z, V& ux,
                                            V& uy, V& uz) {
  using T = typename V::T;
  ux = (x - splat(g.origin[0])) * splat(g.inverse_side);
  uy = (y - splat(g.origin[1])) * splat(g.inverse_side);
  uz = (z - splat(g.origin[2])) * splat(g.inverse_side);
  const V zero = splat(T(0));
  return le_bits(zero, ux) & le_bits(zero, uy) & le_bits(zero, uz) &
         ~le_bits(splat(T(g.n[0])), ux) & ~le_bits(splat(T(g.n[1])), uy) &
         ~le_bits(splat(T(g.n[2])), uz);
}

// Asks for the field's cells of points first .. first + n - 1 of a posed set, so that the
// look-ups that follow overlap their memory latency (no effect on any answer).
template <class V>
MEDSPHERES_KERNEL_INLINE void prefetch_points(const GridView<typename V::T>& g,
                                              const typename V::T* set, int first, int n) {
  if (g.field == nullptr) return;
  constexpr int W = V::W;
  for (int i = first; i < first + n; ++i) {
    V ux, uy, uz;
    const unsigned inside = grid_cell(g, load(set + 3 * i * W), load(set + (3 * i + 1) * W),
                                      load(set + (3 * i + 2) * W), ux, uy, uz);
    if (inside) prefetch_cells(g, ux, uy, uz, inside);
  }
}

// The lanes in which the point (x, y, z) is certainly farther than `far` from every
// element (returned), and those in which it is certainly within `near` of one (`hit`):
// inside the field, by its cell's bounds at the centre and |p - centre|; outside, by the
// elements' bounding box (no hit). Both less the grid's pad, for the rounding of these
// tests in doubles (in floats, the slack in far and near covers theirs).
template <class V>
MEDSPHERES_KERNEL_INLINE unsigned grid_test(const GridView<typename V::T>& g, V x, V y, V z,
                                            typename V::T far, typename V::T near, unsigned& hit) {
  using T = typename V::T;
  V ux, uy, uz;
  const unsigned inside = grid_cell(g, x, y, z, ux, uy, uz);
  const V zero = splat(T(0));
  const T reach = far + g.pad;
  unsigned clear = 0;
  hit = 0;
  if (inside) {
    V cx, cy, cz, upper;
    const V lower = gather_cells(g, ux, uy, uz, inside, cx, cy, cz, upper);
    const V half = splat(T(0.5));
    const V dx = x - ((cx + half) * splat(g.side) + splat(g.origin[0])),
            dy = y - ((cy + half) * splat(g.side) + splat(g.origin[1])),
            dz = z - ((cz + half) * splat(g.side) + splat(g.origin[2]));
    const V centre2 = (dx * dx + dy * dy) + dz * dz;
    const V room = lower * splat(g.unit) - splat(reach);  // clear when room > |p - centre|
    clear = inside & ~le_bits(room, zero) & ~le_bits(room * room, centre2);
    // upper 255: none known.
    const V depth = splat(near - g.pad) - upper * splat(g.unit);  // hit when >= |p - centre|
    hit = inside & ~le_bits(splat(T(254.5)), upper) & le_bits(zero, depth) &
          le_bits(centre2, depth * depth);
  }
  const unsigned outside = ((1u << V::W) - 1) & ~inside;
  if (outside) {
    const V bx = vmax(vmax(splat(g.box_min[0]) - x, x - splat(g.box_max[0])), zero),
            by = vmax(vmax(splat(g.box_min[1]) - y, y - splat(g.box_max[1])), zero),
            bz = vmax(vmax(splat(g.box_min[2]) - z, z - splat(g.box_max[2])), zero);
    if (reach > T(0))
      clear |= outside & ~le_bits((bx * bx + by * by) + bz * bz, splat(reach * reach));
  }
  return clear;
}

// The lanes of `open` in which point i of the posed set may lie within rq of the scene
// (the field does not clear it by more than the slack); those certainly within rq - slack
// of it into `hit`.
template <class V>
MEDSPHERES_KERNEL_INLINE unsigned grid_near(const Ctx<V>& c, const typename V::T* set, int i,
                                            double rq, unsigned open, unsigned& hit) {
  hit = 0;
  if (c.sp.grid.field == nullptr || !open) return 0;  // no element
  constexpr int W = V::W;
  using T = typename V::T;
  const unsigned clear = grid_test(c.sp.grid, load(set + 3 * i * W), load(set + (3 * i + 1) * W),
                                   load(set + (3 * i + 2) * W), T(rq + double(c.p.slack)),
                                   T(rq - double(c.p.slack)), hit);
  hit &= open;
  return open & ~clear;
}

// The lanes of `near` in which point i of a posed set (radius + add: rq) is within rq of
// the scene by the grid's lists (exact, lane by lane): certainly (added to `hit`), or
// maybe (added to `maybe`: within the slack of it).
template <class V>
MEDSPHERES_KERNEL_INLINE void scan_lanes(const Ctx<V>& c, const typename V::T* set, int i,
                                         double rq, unsigned near, unsigned& hit, unsigned& maybe) {
  for (int lane = 0; lane < V::W && near; ++lane) {
    if (!(near >> lane & 1)) continue;
    near &= ~(1u << lane);
    double p[3];
    lane_point<V>(set, i, lane, p);
    const int v = c.scene.classify(p, rq, double(c.p.slack));
    if (v == 1) hit |= 1u << lane;
    if (v == 2) maybe |= 1u << lane;
  }
}

// A link's set `slot` against the scene by the field alone, in the lanes `need`: returns
// the lanes in which some sphere is certainly within r + add of it, and keeps per sphere
// (p.near) the lanes its look-up leaves open, for set_lists.
template <class V>
unsigned set_field(const Ctx<V>& c, int link, int slot, double add, unsigned need) {
  const LinkLayout& l = c.robot.link[link];
  const typename V::T* set = posed(c, link, slot);
  const int begin = static_cast<int>(l.begin[slot]), count = static_cast<int>(l.count[slot]);
  prefetch_points<V>(c.sp.grid, set, 0, count);
  unsigned hit = 0;
  int i = 0;
  for (; i < count && (need & ~hit); ++i) {
    unsigned certain = 0;
    c.p.near[begin + i] = static_cast<unsigned char>(
        grid_near(c, set, i, double(c.sp.r[begin + i]) + add, need & ~hit, certain));
    hit |= certain;
  }
  for (; i < count; ++i) c.p.near[begin + i] = 0;  // every lane of `need` settled
  return hit;
}

// After set_field of the same set and `add`: the lanes of `lanes` in which some sphere
// whose look-up left them open is within r + add of the scene by the grid's lists:
// certainly (returned), or maybe (added to `maybe`).
template <class V>
unsigned set_lists(const Ctx<V>& c, int link, int slot, double add, unsigned lanes,
                   unsigned& maybe) {
  const LinkLayout& l = c.robot.link[link];
  const typename V::T* set = posed(c, link, slot);
  const int begin = static_cast<int>(l.begin[slot]), count = static_cast<int>(l.count[slot]);
  unsigned hit = 0;
  for (int i = 0; i < count && (lanes & ~hit); ++i)
    scan_lanes(c, set, i, double(c.sp.r[begin + i]) + add, c.p.near[begin + i] & lanes & ~hit, hit,
               maybe);
  return hit;
}

// Lanes of `need` in which some sphere of the link's set `slot` is within r + add of the
// scene: certainly (returned), or maybe (added to `maybe`: within the slack of it). The
// field's look-ups of every sphere first, then the lists in the lanes and spheres they
// leave open: a lane that a later sphere's look-up settles reads no list.
template <class V>
unsigned set_scene(const Ctx<V>& c, int link, int slot, double add, unsigned need,
                   unsigned& maybe) {
  const unsigned hit = set_field(c, link, slot, add, need);
  return hit | set_lists(c, link, slot, add, need & ~hit, maybe);
}

// The lanes in which some sphere of link a's set slot_a is within `add` + radii of some
// sphere of link o's set slot_o: certainly (returned) or maybe (added to `maybe`); stops
// when every lane of `need` is certain. A sphere of a farther from o's bounding sphere
// than that in every lane meets no sphere of o, and is skipped (the bounding sphere holds
// o's spheres with room for the rounding: the skip changes no answer); o's set is posed
// only when a sphere of a is not skipped.
template <class V>
unsigned level_within(const Ctx<V>& c, int a, int o, int slot_a, int slot_o, double add,
                      unsigned need, unsigned& maybe) {
  using T = typename V::T;
  constexpr int W = V::W;
  const LinkLayout &la = c.robot.link[a], &lo = c.robot.link[o];
  const int ba = static_cast<int>(la.begin[slot_a]), na = static_cast<int>(la.count[slot_a]);
  const int bb = static_cast<int>(lo.begin[slot_o]), nb = static_cast<int>(lo.count[slot_o]);
  const T* pa = posed(c, a, slot_a);
  const T* bound = posed(c, o, kBoundSlot);
  const T* pb = nullptr;
  const double rb = double(c.sp.bound[4 * o + 3]);
  const T slack = c.p.slack;
  unsigned hit = 0, near = 0;
  const V bx = load(bound), by = load(bound + W), bz = load(bound + 2 * W);
  for (int i = 0; i < na; ++i) {
    const V ax = load(pa + 3 * i * W), ay = load(pa + (3 * i + 1) * W),
            az = load(pa + (3 * i + 2) * W);
    const double ra = double(c.sp.r[ba + i]) + add;
    const double cull = ra + rb + 1e-9 * (1.0 + rb) + double(slack);
    if (cull < 0.0) continue;
    const V ex = ax - bx, ey = ay - by, ez = az - bz;
    const unsigned open =
        need & ~hit & le_bits((ex * ex + ey * ey) + ez * ez, splat(T(cull * cull)));
    if (!open) continue;
    if (pb == nullptr) pb = posed(c, o, slot_o);
    for (int j = 0; j < nb; ++j) {
      const T reach = T(ra + double(c.sp.r[bb + j]));
      if (reach + slack < T(0)) continue;
      const V dx = ax - load(pb + 3 * j * W), dy = ay - load(pb + (3 * j + 1) * W),
              dz = az - load(pb + (3 * j + 2) * W);
      const V d2 = (dx * dx + dy * dy) + dz * dz;
      const T in = reach - slack;
      if (in >= T(0)) hit |= le_bits(d2, splat(in * in));
      if (slack > T(0)) near |= open & le_bits(d2, splat((reach + slack) * (reach + slack)));
    }
    if ((hit & need) == need) break;
  }
  maybe |= near & need;
  return hit & need;
}

// The lanes of `open` in which link's bounding sphere may come within the margin of the
// scene.
template <class V>
MEDSPHERES_KERNEL_INLINE unsigned scene_near(const Ctx<V>& c, int link, unsigned open) {
  if (c.robot.never_near_scene(link)) return 0;
  const double rq = double(c.sp.bound[4 * link + 3]) + c.b.margin + c.b.allowance;
  unsigned hit = 0;  // of the bounding sphere: says nothing of the link
  return grid_near(c, posed(c, link, kBoundSlot), 0, rq, open, hit);
}

// The lanes of `open` in which the bounding spheres of self pair k's links may come within
// the margin of each other.
template <class V>
MEDSPHERES_KERNEL_INLINE unsigned pair_near(const Ctx<V>& c, int k, unsigned open) {
  using T = typename V::T;
  constexpr int W = V::W;
  const T* ba = posed(c, static_cast<int>(c.robot.pair_a[k]), kBoundSlot);
  const T* bo = posed(c, static_cast<int>(c.robot.pair_b[k]), kBoundSlot);
  const V dx = load(ba) - load(bo), dy = load(ba + W) - load(bo + W),
          dz = load(ba + 2 * W) - load(bo + 2 * W);
  return open & le_bits((dx * dx + dy * dy) + dz * dz, splat(c.sp.pair_reach2[k]));
}

// The fine index (pair_table.h) of every table slot's position in each lane of the pass
// (0 beyond its limits, and in the lanes past the pass's width) and the lanes within
// them, computed on a pass's first table look-up.
struct TableCells {
  bool ready = false;
  unsigned inside[kMaxTableSlots];
  alignas(32) std::uint32_t fine[kMaxTableSlots * kLanes];
};

// The fine indices of the positions q[0 .. W) of a table slot: (q - lower) * inverse in
// doubles, rounded down, within [0, kFineCells) (else 0) into out; returns the lanes within.
template <int W>
MEDSPHERES_KERNEL_INLINE unsigned slot_cells(const TableSlot& slot, const double* q,
                                             std::uint32_t* out) {
  unsigned inside = 0;
  for (int h = 0; h < W / kHalf; ++h) {
    const VD x = (load(q + h * kHalf) - splat(slot.lower)) * splat(slot.inverse);
    const unsigned in = le_bits(splat(0.0), x) & ~le_bits(splat(kFineCells), x);
    truncate_cells(x, in, out + h * kHalf);
    inside |= in << (h * kHalf);
  }
  return inside;
}

// The lanes of `open` whose joint positions fall in a free cell of self pair k's table
// (pair_table.h): the pair's sets are farther apart than the margin there, so its test
// would find no collision. From the positions in doubles (the lanes of the pass's half).
template <class V>
MEDSPHERES_KERNEL_INLINE unsigned table_free(const Ctx<V>& c, int k, unsigned open,
                                             TableCells& cells) {
  constexpr int W = V::W;
  const PairTableView& t = c.robot.table[k];
  if (t.bits == nullptr) return 0;
  if (!cells.ready) {
    const double* q = c.b.q + (W == kLanes ? 0 : c.b.half * kHalf);
    for (int s = 0; s < c.robot.table_slots; ++s) {
      const TableSlot& slot = c.robot.table_slot[s];
      cells.inside[s] = slot_cells<W>(slot, q + slot.source * kLanes, cells.fine + s * kLanes);
      for (int lane = W; lane < kLanes; ++lane) cells.fine[s * kLanes + lane] = 0;
    }
    cells.ready = true;
  }
  unsigned inside = open;
  for (int j = 0; j < t.sources; ++j) inside &= cells.inside[t.slot[j]];
  if (!inside || t.all_free) return inside;
  return table_bits(t, cells.fine) & inside;
}

// The lanes of `open` in which self pair k's sets must be tested (spheres mode): those its
// table (if any) and its bounding spheres leave. A table free everywhere answers by the
// limits alone, before the bounding spheres; another after them, in the lanes they leave.
template <class V>
MEDSPHERES_KERNEL_INLINE unsigned pair_need(const Ctx<V>& c, int k, unsigned open,
                                            TableCells& cells) {
  const KernelRobot& robot = c.robot;
  const bool everywhere = robot.table && robot.table[k].all_free;
  const unsigned lanes = everywhere ? open & ~table_free(c, k, open, cells) : open;
  unsigned need = lanes ? pair_near(c, k, lanes) : 0u;
  if (need && robot.table && !everywhere) need &= ~table_free(c, k, need, cells);
  return need;
}

// The bounding-sphere tests of every link against the scene, for the lanes `open`, into
// near[0 .. links): independent of one another, so run back to back (their look-ups
// overlap) before any finer test.
template <class V>
void near_links(const Ctx<V>& c, unsigned open, unsigned char* near) {
  const KernelRobot& robot = c.robot;
  for (int link = 0; link < robot.links; ++link)
    if (!robot.never_near_scene(link))
      prefetch_points<V>(c.sp.grid, posed(c, link, kBoundSlot), 0, 1);
  for (int link = 0; link < robot.links; ++link)
    near[link] = static_cast<unsigned char>(scene_near(c, link, open));
}

// near_links, then every self pair's bounding spheres into near[links .. links + pairs).
template <class V>
void near_all(const Ctx<V>& c, unsigned open, unsigned char* near) {
  const KernelRobot& robot = c.robot;
  near_links(c, open, near);
  for (int k = 0; k < robot.pairs; ++k)
    near[robot.links + k] = static_cast<unsigned char>(c.b.self ? pair_near(c, k, open) : 0u);
}

// Bounds mode, one level of a pair (link against the scene when o < 0, else the self pair
// link, o) in the lanes `pending`: the lanes certainly free leave `pending`, those
// certainly colliding leave it for the result. Unsure tests: a covering sphere maybe
// within the margin keeps the lane pending and joins `maybe_near` (the pair may be free
// in doubles); an inner sphere maybe within it joins `maybe_hit` (the lane may collide).
template <class V>
unsigned pair_level(const Ctx<V>& c, int link, int o, int level, unsigned& pending,
                    unsigned& maybe_near, unsigned& maybe_hit) {
  const LinkLayout& la = c.robot.link[link];
  const int outer = level ? kFineOuter : kOuter, inner = level ? kFineInner : kInner;
  const bool self = o >= 0;
  const double far = c.b.margin + c.b.allowance, near = c.b.margin - c.b.allowance;
  if (la.count[outer] > 0 && (!self || c.robot.link[o].count[outer] > 0)) {
    unsigned maybe = 0;
    const unsigned hit = self ? level_within(c, link, o, outer, outer, far, pending, maybe)
                              : set_scene(c, link, outer, far, pending, maybe);
    maybe_near |= maybe & ~hit;
    pending = hit | maybe;
  }
  unsigned out = 0;
  if (la.count[inner] > 0 && (!self || c.robot.link[o].count[inner] > 0) && pending) {
    unsigned maybe = 0;
    out = self ? level_within(c, link, o, inner, inner, near, pending, maybe)
               : set_scene(c, link, inner, near, pending, maybe);
    maybe_hit |= maybe & ~out;
    pending &= ~out;
  }
  return out;
}

// The bounds mode level by level: every pair at the planner's level first (a certain
// collision found there spares the fine level of every other pair), then the fine level
// of the pairs still open; within a level the pairs in the robot's order (test_order.h:
// a lane leaves `open` only by a certain collision, and a pair's pending lanes depend on
// that pair alone, so every order gives the same verdicts and undecided pairs). p.pending holds per
// link (scene) and per self pair the lanes still undecided, p.unsure those in which a covering test
// of the pair was unsure. Returns the open lanes, adds the undecided ones to b.undecided; `unsure`:
// the open lanes whose verdict may differ in doubles (a pair still pending after an unsure covering
// test may be free there; an unsure inner test may collide there). The order is the bounds
// order (robot.bounds_order, learnt from the tests' proofs: with b.hits every test runs in every
// lane and counts the lanes it proves colliding). A probe (b.probe > 0) runs the order's tests
// [b.probe_from, b.probe) at the planner's level only: a lane it proves colliding is proved by
// the same test in the whole run.
// A probe's bounding-sphere test of test k (link k against the scene, or self pair k -
// links), in the lanes `open` (kept out of run_bounds' loop, which runs without a probe
// mostly).
template <class V>
__attribute__((noinline)) unsigned char probe_near(const Ctx<V>& c, int k, unsigned open) {
  const int links = c.robot.links;
  return static_cast<unsigned char>(k < links ? scene_near(c, k, open)
                                              : pair_near(c, k - links, open));
}

template <class V>
unsigned run_bounds(const Ctx<V>& c, unsigned& unsure) {
  const KernelRobot& robot = c.robot;
  unsigned char* pending = c.p.pending;
  unsigned char* near = c.p.unsure;
  const int probe = c.b.probe, tests = probe > 0 ? probe : robot.links + robot.pairs;
  // A probe tests the bounding spheres of its own tests only (on their turn, below).
  for (int k = 0; k < robot.links + robot.pairs; ++k) near[k] = pending[k] = 0;
  if (probe == 0) near_all(c, c.p.lanes, pending);
  unsigned open = c.p.lanes, maybe_hit = 0;
  for (int level = 0; level < (robot.fine && probe == 0 ? 2 : 1); ++level)
    for (int t = probe > 0 ? c.b.probe_from : 0; t < tests && open; ++t) {
      const int k = static_cast<int>(robot.bounds_order[t]);
      if (k >= robot.links && !c.b.self) continue;
      const int a = k < robot.links ? k : static_cast<int>(robot.pair_a[k - robot.links]),
                o = k < robot.links ? -1 : static_cast<int>(robot.pair_b[k - robot.links]);
      if (probe > 0) pending[k] = probe_near(c, k, open);
      unsigned p = pending[k] & open, m = near[k], hit = 0;
      if (p) hit = pair_level(c, a, o, level, p, m, maybe_hit);
      if (c.b.hits)
        c.b.hits[k] += static_cast<std::uint32_t>(__builtin_popcount(hit));
      else
        open &= ~hit;
      pending[k] = static_cast<unsigned char>(p);
      near[k] = static_cast<unsigned char>(m);
    }
  unsure = maybe_hit;
  for (int k = 0; k < robot.links + robot.pairs; ++k) {
    unsure |= near[k] & pending[k];
    c.b.undecided |= pending[k] & open;
  }
  unsure &= open;
  return open;
}

// The spheres mode: the tests (each link against the scene, each self pair) in the
// robot's order (test_order.h), each in the lanes still open (a link's lists, which its
// field's look-ups leave open, in the lanes still open after every test: a lane that
// another test finds colliding reads none), a self pair's bounding
// spheres only when it is reached, its sets only in the lanes its table (if any) leaves. The links'
// bounding spheres against the scene (near_links) run after the order's first robot.head tests
// (those that find most configurations colliding: when they leave no lane open, the look-ups are
// spared), a head link's own on its turn. Any order gives the same verdicts: a lane leaves `open`
// only by a certain collision, and every test runs in every other lane. With b.hits
// (learning), every test runs in every lane and counts the lanes it finds colliding.
template <class V>
unsigned run_spheres(const Ctx<V>& c, unsigned& unsure) {
  const KernelRobot& robot = c.robot;
  unsigned char* near = c.p.pending;
  unsigned open = c.p.lanes, maybe = 0;
  TableCells cells;
  int* lists = c.p.lists;  // the links whose lists wait for the end (not when learning)
  int waiting = 0;
  for (int t = 0; t < robot.links + robot.pairs && open; ++t) {
    if (t == robot.head) near_links(c, open, near);
    const int k = static_cast<int>(robot.order[t]);
    unsigned hit = 0;
    if (k < robot.links) {
      const unsigned need = (t < robot.head ? scene_near(c, k, open) : near[k]) & open;
      if (need) {
        hit = set_field(c, k, robot.link[k].spheres, c.b.margin, need);
        if (c.b.hits)
          hit |= set_lists(c, k, robot.link[k].spheres, c.b.margin, need & ~hit, maybe);
        else
          lists[waiting++] = k;
      }
    } else if (c.b.self) {
      const int a = static_cast<int>(robot.pair_a[k - robot.links]),
                o = static_cast<int>(robot.pair_b[k - robot.links]);
      const unsigned need = pair_need(c, k - robot.links, open, cells);
      if (need)
        hit = level_within(c, a, o, robot.link[a].spheres, robot.link[o].spheres, c.b.margin, need,
                           maybe);
    }
    if (c.b.hits) {
      c.b.hits[k] += static_cast<std::uint32_t>(__builtin_popcount(hit));
      continue;
    }
    open &= ~hit;
    if (hit && c.b.any) break;
  }
  // With b.any the first lane found colliding decides the block: nothing more runs.
  const bool decided = c.b.any && open != c.p.lanes;
  for (int w = 0; w < waiting && open && !decided; ++w) {
    open &= ~set_lists(c, lists[w], robot.link[lists[w]].spheres, c.b.margin, open, maybe);
    if (c.b.any && open != c.p.lanes) break;
  }
  unsure = c.b.any && open != c.p.lanes ? 0u : maybe & open;
  return open;
}

// One pass; returns the colliding lanes (certain), sets `unsure`.
template <class V>
unsigned run_pass(const Ctx<V>& c, unsigned& unsure) {
  for (int k = 0; k < c.robot.links * kSlots; ++k) c.p.posed_flag[k] = 0;
  const unsigned open = c.b.bounds ? run_bounds(c, unsure) : run_spheres(c, unsure);
  return c.p.lanes & ~open;
}

// The bounds mode's undecided pairs to the sink: those pending in the lanes `open`, of
// `width` lanes (a half's in doubles, b.half its index; every lane in floats, b.half -1).
void sink_pairs(const KernelRobot& robot, Block& b, unsigned open, int width) {
  for (int k = 0; k < robot.links + robot.pairs; ++k)
    for (int lane = 0; lane < width; ++lane)
      if (b.pending[k] & open & 1u << lane)
        k < robot.links ? b.sink(b, lane, k, -1)
                        : b.sink(b, lane, static_cast<int>(robot.pair_a[k - robot.links]),
                                 static_cast<int>(robot.pair_b[k - robot.links]));
}

// A pass over block b's workspace, its frames and posed points in T, in the lanes `lanes`
// (slack 0).
template <class T>
Pass<T> pass_of(const Block& b, const T* frames, T* posed, unsigned lanes) {
  Pass<T> p;
  p.frames = frames;
  p.posed = posed;
  p.posed_flag = b.posed_flag;
  p.near = b.near;
  p.lists = b.lists;
  p.pending = b.pending;
  p.unsure = b.unsure;
  p.lanes = lanes;
  return p;
}

// The double pass over the lanes `lanes` of half h: the documented tests; the sink sees
// the undecided pairs.
void run_doubles(const KernelRobot& robot, const SceneGrid& scene, Block& b, int h,
                 unsigned lanes) {
  Pass<double> p = pass_of(b, b.frames + h * robot.frames * 12 * kHalf, b.posed, lanes);
  const unsigned undecided = b.undecided;
  b.undecided = 0;
  b.half = h;
  const Ctx<VD> c{robot, robot.d, scene, b, p};
  unsigned unsure = 0;
  const unsigned hit = run_pass(c, unsure);
  const unsigned open = lanes & ~hit;
  if (b.sink && b.bounds) sink_pairs(robot, b, open, kHalf);
  const unsigned shift = static_cast<unsigned>(h * kHalf);
  b.colliding |= hit << shift;
  b.undecided = undecided | (b.undecided & open) << shift;
}

// The float pass over block b's lanes and workspace.
Pass<float> float_pass(const Block& b) {
  Pass<float> p = pass_of(b, b.frames_f, b.posed_f, b.lanes);
  p.slack = b.slack;
  return p;
}

// The double pass over block b's lanes `recheck`, half by half; then a colliding lane is
// no longer undecided.
void recheck_doubles(const KernelRobot& robot, const SceneGrid& scene, Block& b, unsigned recheck) {
  for (int h = 0; h < 2; ++h) {
    const unsigned lanes = recheck >> (h * kHalf) & 0xFu;
    if (!lanes) continue;
    pose_frames(robot, b, h);
    run_doubles(robot, scene, b, h, lanes);
  }
  b.undecided &= ~b.colliding;
}

// The float pass poses the frames in floats; the double pass poses them again in doubles
// for the halves that hold a lane to check again.
void run_block(const KernelRobot& robot, const SceneGrid& scene, Block& b) {
  b.colliding = b.undecided = b.rechecked = 0;
  unsigned recheck = b.lanes;
  if (b.floats) {
    pose_frames_float(robot, b);
    Pass<float> p = float_pass(b);
    const Ctx<VF> c{robot, robot.f, scene, b, p};
    unsigned unsure = 0;
    b.colliding = run_pass(c, unsure);
    recheck = b.probe > 0 ? 0u : unsure & ~b.colliding;  // a probe's open lanes run again
    b.undecided &= ~(b.colliding | recheck);
    b.rechecked = recheck;
    // A lane the floats leave undecided with every test certain has the double pass's
    // pending pairs (each test's outcome is the same in doubles): the sink takes them now.
    if (b.sink && b.bounds && b.undecided) {
      b.half = -1;
      sink_pairs(robot, b, b.undecided, kLanes);
    }
  }
  recheck_doubles(robot, scene, b, recheck);
}

// ---- Batches (block.h, Batch): the spheres mode's set tests compacted across blocks.

// Frame f of the items' lanes (block << 3 | lane, n of them) into the batch's frames (the
// lanes past n repeat item 0's).
void gather_frame(const Batch& t, int f, const std::uint16_t* items, int n) {
  float* out = t.frames_f + f * 12 * kLanes;
  for (int s = 0; s < kLanes; ++s) {
    const int item = items[s < n ? s : 0];
    const float* in = t.blocks[item >> 3].frames_f + f * 12 * kLanes + (item & 7);
    for (int e = 0; e < 12; ++e) out[e * kLanes + s] = in[e * kLanes];
  }
}

// Test k's sets (link k against the scene, or self pair k - links) in n <= kLanes items,
// gathered into the lanes of c's pass (its frames the batch's): the items found colliding
// to their blocks' `colliding`, those maybe colliding to the batch's `unsure`. The same
// operations per lane as run_spheres' test of the item in its own block.
void run_items(const Ctx<VF>& c, Batch& t, int k, const std::uint16_t* items, int n) {
  const KernelRobot& robot = c.robot;
  const bool link = k < robot.links;
  const int a = link ? k : static_cast<int>(robot.pair_a[k - robot.links]),
            o = link ? -1 : static_cast<int>(robot.pair_b[k - robot.links]);
  gather_frame(t, robot.link[a].frame, items, n);
  if (o >= 0 && robot.link[o].frame != robot.link[a].frame)
    gather_frame(t, robot.link[o].frame, items, n);
  for (int s = 0; s < kSlots; ++s) {
    c.p.posed_flag[a * kSlots + s] = 0;
    if (o >= 0) c.p.posed_flag[o * kSlots + s] = 0;
  }
  const unsigned lanes = (1u << n) - 1;
  c.p.lanes = lanes;
  unsigned maybe = 0, hit = 0;
  if (link) {
    hit = set_field(c, a, robot.link[a].spheres, c.b.margin, lanes);
    hit |= set_lists(c, a, robot.link[a].spheres, c.b.margin, lanes & ~hit, maybe);
  } else {
    hit = level_within(c, a, o, robot.link[a].spheres, robot.link[o].spheres, c.b.margin, lanes,
                       maybe);
  }
  for (int s = 0; s < n; ++s) {
    const unsigned bit = 1u << (items[s] & 7);
    if (hit >> s & 1) t.blocks[items[s] >> 3].colliding |= bit;
    if (maybe >> s & 1) t.unsure[items[s] >> 3] |= bit;
  }
}

// Each float block's frames and bounding tests: the lanes each test must run in, into
// t.need (none for a block in doubles, which runs whole here).
void batch_bounds(const KernelRobot& robot, const SceneGrid& scene, Batch& t) {
  const int tests = robot.links + robot.pairs;
  for (int j = 0; j < t.count; ++j) {
    Block& b = t.blocks[j];
    unsigned char* need = t.need + j * tests;
    t.unsure[j] = 0;
    for (int k = 0; k < tests; ++k) need[k] = 0;
    if (!b.floats) {
      run_block(robot, scene, b);
      continue;
    }
    b.colliding = b.undecided = b.rechecked = 0;
    pose_frames_float(robot, b);
    Pass<float> p = float_pass(b);
    const Ctx<VF> c{robot, robot.f, scene, b, p};
    for (int k = 0; k < robot.links * kSlots; ++k) p.posed_flag[k] = 0;
    near_links(c, b.lanes, need);
    TableCells cells;
    for (int k = 0; b.self && k < robot.pairs; ++k)
      need[robot.links + k] = static_cast<unsigned char>(pair_need(c, k, b.lanes, cells));
  }
}

// The spheres mode over a batch: batch_bounds, then the tests in the robot's order, each in
// groups of kLanes items (a block's lane that the test must run in and that no test has
// found colliding), then the double pass of each float block's unsure lanes, as run_block.
void run_batch(const KernelRobot& robot, const SceneGrid& scene, Batch& t) {
  if (t.count == 0) return;
  batch_bounds(robot, scene, t);
  const int tests = robot.links + robot.pairs;
  Pass<float> p = float_pass(t.blocks[0]);  // margin, slack, self: the same in every block
  p.frames = t.frames_f;
  const Ctx<VF> c{robot, robot.f, scene, t.blocks[0], p};
  std::uint16_t items[kLanes];
  for (int i = 0; i < tests; ++i) {
    const int k = static_cast<int>(robot.order[i]);
    int n = 0;
    for (int j = 0; j < t.count; ++j)
      for (unsigned lanes = t.need[j * tests + k] & ~t.blocks[j].colliding; lanes;
           lanes &= lanes - 1) {
        items[n++] = static_cast<std::uint16_t>(j << 3 | __builtin_ctz(lanes));
        if (n == kLanes) {
          run_items(c, t, k, items, n);
          n = 0;
        }
      }
    if (n) run_items(c, t, k, items, n);
  }
  for (int j = 0; j < t.count; ++j) {
    Block& b = t.blocks[j];
    if (!b.floats) continue;
    b.rechecked = t.unsure[j] & b.lanes & ~b.colliding;
    recheck_doubles(robot, scene, b, b.rechecked);
  }
}

}  // namespace
}  // namespace medspheres::check::detail
