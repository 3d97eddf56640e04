// The kernel with plain lane types: four doubles or eight floats, one operation each (the
// path for machines without AVX2, and the reference the AVX2 path must match bit for bit).

#include "block.h"

namespace medspheres::check::detail {
namespace {

template <class S, int N>
struct Lanes {
  using T = S;
  static constexpr int W = N;
  S v[N];
};
using VD = Lanes<double, kHalf>;
using VF = Lanes<float, kLanes>;

template <class S, int N>
Lanes<S, N> splat_as(S a) {
  Lanes<S, N> r;
  for (S& x : r.v) x = a;
  return r;
}
VD splat(double a) {
  return splat_as<double, kHalf>(a);
}
VF splat(float a) {
  return splat_as<float, kLanes>(a);
}
template <class S, int N>
Lanes<S, N> load_as(const S* p) {
  Lanes<S, N> r;
  for (int l = 0; l < N; ++l) r.v[l] = p[l];
  return r;
}
VD load(const double* p) {
  return load_as<double, kHalf>(p);
}
VF load(const float* p) {
  return load_as<float, kLanes>(p);
}
template <class S, int N>
void store(S* p, Lanes<S, N> a) {
  for (int l = 0; l < N; ++l) p[l] = a.v[l];
}
template <class S, int N>
Lanes<S, N> operator+(Lanes<S, N> a, Lanes<S, N> b) {
  for (int l = 0; l < N; ++l) a.v[l] += b.v[l];
  return a;
}
template <class S, int N>
Lanes<S, N> operator-(Lanes<S, N> a, Lanes<S, N> b) {
  for (int l = 0; l < N; ++l) a.v[l] -= b.v[l];
  return a;
}
template <class S, int N>
Lanes<S, N> operator*(Lanes<S, N> a, Lanes<S, N> b) {
  for (int l = 0; l < N; ++l) a.v[l] *= b.v[l];
  return a;
}
template <class S, int N>
unsigned le_bits(Lanes<S, N> a, Lanes<S, N> b) {
  unsigned m = 0;
  for (int l = 0; l < N; ++l) m |= (a.v[l] <= b.v[l] ? 1u : 0u) << l;
  return m;
}
VF to_float(VD lo, VD hi) {
  VF r;
  for (int l = 0; l < kHalf; ++l) {
    r.v[l] = static_cast<float>(lo.v[l]);
    r.v[kHalf + l] = static_cast<float>(hi.v[l]);
  }
  return r;
}
template <class S, int N>
Lanes<S, N> vmax(Lanes<S, N> a, Lanes<S, N> b) {
  for (int l = 0; l < N; ++l) a.v[l] = a.v[l] > b.v[l] ? a.v[l] : b.v[l];
  return a;
}
template <class S, int N>
Lanes<S, N> gather_cells(const GridView<S>& g, Lanes<S, N> ux, Lanes<S, N> uy, Lanes<S, N> uz,
                         unsigned inside, Lanes<S, N>& cx, Lanes<S, N>& cy, Lanes<S, N>& cz,
                         Lanes<S, N>& upper) {
  Lanes<S, N> lower;
  for (int l = 0; l < N; ++l) {
    const bool in = inside >> l & 1;
    const int i = in ? static_cast<int>(ux.v[l]) : 0, j = in ? static_cast<int>(uy.v[l]) : 0,
              k = in ? static_cast<int>(uz.v[l]) : 0;
    cx.v[l] = S(i);
    cy.v[l] = S(j);
    cz.v[l] = S(k);
    const int bytes = in ? g.field[i + g.n[0] * (j + g.n[1] * k)] : 0;
    lower.v[l] = S(bytes & 0xFF);
    upper.v[l] = S(bytes >> 8 & 0xFF);
  }
  return lower;
}

// Asks for the cells that gather_cells would read in the lanes `inside` (no effect on any
// answer).
template <class S, int N>
void prefetch_cells(const GridView<S>& g, Lanes<S, N> ux, Lanes<S, N> uy, Lanes<S, N> uz,
                    unsigned inside) {
  for (int l = 0; l < N; ++l)
    if (inside >> l & 1)
      __builtin_prefetch(
          g.field + (static_cast<int>(ux.v[l]) +
                     g.n[0] * (static_cast<int>(uy.v[l]) + g.n[1] * static_cast<int>(uz.v[l]))));
}

void truncate_cells(VD x, unsigned in, std::uint32_t* out) {
  for (int l = 0; l < kHalf; ++l) out[l] = in >> l & 1 ? static_cast<std::uint32_t>(x.v[l]) : 0u;
}

unsigned table_bits(const PairTableView& t, const std::uint32_t* fine) {
  unsigned out = 0;
  for (int l = 0; l < kLanes; ++l) {
    std::uint32_t cell = 0;
    for (int j = 0; j < t.sources; ++j)
      cell += (fine[t.slot[j] * kLanes + l] >> t.shift[j]) * t.stride[j];
    out |= static_cast<unsigned>(t.bits[cell >> 6] >> (cell & 63) & 1) << l;
  }
  return out;
}

}  // namespace
}  // namespace medspheres::check::detail

#include "kernel_body.h"

namespace medspheres::check::detail {

void run_block_scalar(const KernelRobot& robot, const SceneGrid& scene, Block& block) {
  run_block(robot, scene, block);
}

void run_batch_scalar(const KernelRobot& robot, const SceneGrid& scene, Batch& batch) {
  run_batch(robot, scene, batch);
}

}  // namespace medspheres::check::detail
