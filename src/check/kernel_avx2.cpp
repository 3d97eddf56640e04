// The kernel with AVX2 lanes (four doubles or eight floats in one register). Built with
// -mavx2 and without FMA, so that every lane performs the scalar kernel's operations
// exactly (no fused multiply-add, which rounds once where the scalar path rounds twice);
// called only when the processor has AVX2 (robot_checker.cpp).

#include <immintrin.h>

#include "block.h"

namespace medspheres::check::detail {
namespace {

struct VD {
  using T = double;
  static constexpr int W = kHalf;
  __m256d v;
};
struct VF {
  using T = float;
  static constexpr int W = kLanes;
  __m256 v;
};

VD splat(double a) {
  return {_mm256_set1_pd(a)};
}
VF splat(float a) {
  return {_mm256_set1_ps(a)};
}
VD load(const double* p) {
  return {_mm256_loadu_pd(p)};
}
VF load(const float* p) {
  return {_mm256_loadu_ps(p)};
}
void store(double* p, VD a) {
  _mm256_storeu_pd(p, a.v);
}
void store(float* p, VF a) {
  _mm256_storeu_ps(p, a.v);
}
VD operator+(VD a, VD b) {
  return {_mm256_add_pd(a.v, b.v)};
}
VD operator-(VD a, VD b) {
  return {_mm256_sub_pd(a.v, b.v)};
}
VD operator*(VD a, VD b) {
  return {_mm256_mul_pd(a.v, b.v)};
}
VF operator+(VF a, VF b) {
  return {_mm256_add_ps(a.v, b.v)};
}
VF operator-(VF a, VF b) {
  return {_mm256_sub_ps(a.v, b.v)};
}
VF operator*(VF a, VF b) {
  return {_mm256_mul_ps(a.v, b.v)};
}
unsigned le_bits(VD a, VD b) {
  return static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ)));
}
unsigned le_bits(VF a, VF b) {
  return static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)));
}
VF to_float(VD lo, VD hi) {
  return {_mm256_set_m128(_mm256_cvtpd_ps(hi.v), _mm256_cvtpd_ps(lo.v))};
}

VD vmax(VD a, VD b) {
  return {_mm256_max_pd(a.v, b.v)};
}
VF vmax(VF a, VF b) {
  return {_mm256_max_ps(a.v, b.v)};
}

// Lane bits as a mask of 32-bit lanes.
__m256i mask8(unsigned bits) {
  const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  const __m256i b = _mm256_and_si256(_mm256_set1_epi32(int(bits)), bit);
  return _mm256_cmpeq_epi32(b, bit);
}

VF gather_cells(const GridView<float>& g, VF ux, VF uy, VF uz, unsigned inside, VF& cx, VF& cy,
                VF& cz, VF& upper) {
  const __m256i mask = mask8(inside);
  const __m256i ix = _mm256_and_si256(_mm256_cvttps_epi32(ux.v), mask);
  const __m256i iy = _mm256_and_si256(_mm256_cvttps_epi32(uy.v), mask);
  const __m256i iz = _mm256_and_si256(_mm256_cvttps_epi32(uz.v), mask);
  cx.v = _mm256_cvtepi32_ps(ix);
  cy.v = _mm256_cvtepi32_ps(iy);
  cz.v = _mm256_cvtepi32_ps(iz);
  const __m256i cell = _mm256_add_epi32(
      ix,
      _mm256_mullo_epi32(_mm256_set1_epi32(g.n[0]),
                         _mm256_add_epi32(iy, _mm256_mullo_epi32(_mm256_set1_epi32(g.n[1]), iz))));
  // Two bytes a cell: the byte offset is twice the index.
  const __m256i bytes = _mm256_mask_i32gather_epi32(
      _mm256_setzero_si256(), reinterpret_cast<const int*>(g.field), cell, mask, 2);
  const __m256i ff = _mm256_set1_epi32(0xFF);
  upper.v = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(bytes, 8), ff));
  return {_mm256_cvtepi32_ps(_mm256_and_si256(bytes, ff))};
}

VD gather_cells(const GridView<double>& g, VD ux, VD uy, VD uz, unsigned inside, VD& cx, VD& cy,
                VD& cz, VD& upper) {
  const __m128i mask = _mm256_castsi256_si128(mask8(inside));
  const __m128i ix = _mm_and_si128(_mm256_cvttpd_epi32(ux.v), mask);
  const __m128i iy = _mm_and_si128(_mm256_cvttpd_epi32(uy.v), mask);
  const __m128i iz = _mm_and_si128(_mm256_cvttpd_epi32(uz.v), mask);
  cx.v = _mm256_cvtepi32_pd(ix);
  cy.v = _mm256_cvtepi32_pd(iy);
  cz.v = _mm256_cvtepi32_pd(iz);
  const __m128i cell = _mm_add_epi32(
      ix, _mm_mullo_epi32(_mm_set1_epi32(g.n[0]),
                          _mm_add_epi32(iy, _mm_mullo_epi32(_mm_set1_epi32(g.n[1]), iz))));
  const __m128i bytes = _mm_mask_i32gather_epi32(
      _mm_setzero_si128(), reinterpret_cast<const int*>(g.field), cell, mask, 2);
  const __m128i ff = _mm_set1_epi32(0xFF);
  upper.v = _mm256_cvtepi32_pd(_mm_and_si128(_mm_srli_epi32(bytes, 8), ff));
  return {_mm256_cvtepi32_pd(_mm_and_si128(bytes, ff))};
}

// Asks for the cells that gather_cells would read in the lanes `inside` (no effect on any
// answer).
template <class V>
void prefetch_cells(const GridView<typename V::T>& g, V ux, V uy, V uz, unsigned inside) {
  alignas(32) typename V::T x[V::W], y[V::W], z[V::W];
  store(x, ux);
  store(y, uy);
  store(z, uz);
  for (int l = 0; l < V::W; ++l)
    if (inside >> l & 1)
      _mm_prefetch(
          reinterpret_cast<const char*>(
              g.field + (static_cast<int>(x[l]) +
                         g.n[0] * (static_cast<int>(y[l]) + g.n[1] * static_cast<int>(z[l])))),
          _MM_HINT_T0);
}

void truncate_cells(VD x, unsigned in, std::uint32_t* out) {
  const __m128i mask = _mm256_castsi256_si128(mask8(in));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_and_si128(_mm256_cvttpd_epi32(x.v), mask));
}

// The table's bits read as 32-bit words (x86-64 is little-endian: bit c of the 64-bit
// words is bit c & 31 of 32-bit word c >> 5).
unsigned table_bits(const PairTableView& t, const std::uint32_t* fine) {
  __m256i cell = _mm256_setzero_si256();
  for (int j = 0; j < t.sources; ++j) {
    const __m256i f =
        _mm256_load_si256(reinterpret_cast<const __m256i*>(fine + t.slot[j] * kLanes));
    cell = _mm256_add_epi32(cell, _mm256_mullo_epi32(_mm256_srli_epi32(f, t.shift[j]),
                                                     _mm256_set1_epi32(int(t.stride[j]))));
  }
  const __m256i word =
      _mm256_i32gather_epi32(reinterpret_cast<const int*>(t.bits), _mm256_srli_epi32(cell, 5), 4);
  const __m256i one = _mm256_set1_epi32(1);
  const __m256i bit =
      _mm256_and_si256(_mm256_srlv_epi32(word, _mm256_and_si256(cell, _mm256_set1_epi32(31))), one);
  return static_cast<unsigned>(
      _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(bit, one))));
}

}  // namespace
}  // namespace medspheres::check::detail

#include "kernel_body.h"

namespace medspheres::check::detail {

void run_block_avx2(const KernelRobot& robot, const SceneGrid& scene, Block& block) {
  run_block(robot, scene, block);
}

void run_batch_avx2(const KernelRobot& robot, const SceneGrid& scene, Batch& batch) {
  run_batch(robot, scene, batch);
}

}  // namespace medspheres::check::detail
