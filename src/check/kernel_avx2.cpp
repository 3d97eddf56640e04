// The kernel with AVX2 lanes (four doubles in one register). Built with -mavx2 and without
// FMA, so that every lane performs the scalar kernel's operations exactly (no fused
// multiply-add, which rounds once where the scalar path rounds twice); called only when
// the processor has AVX2 (robot_checker.cpp).

#include <immintrin.h>

#include "block.h"

namespace medspheres::check::detail {
namespace {

struct V {
  __m256d v;
};

V splat(double a) {
  return {_mm256_set1_pd(a)};
}
V load(const double* p) {
  return {_mm256_loadu_pd(p)};
}
void store(double* p, V a) {
  _mm256_storeu_pd(p, a.v);
}
V operator+(V a, V b) {
  return {_mm256_add_pd(a.v, b.v)};
}
V operator-(V a, V b) {
  return {_mm256_sub_pd(a.v, b.v)};
}
V operator*(V a, V b) {
  return {_mm256_mul_pd(a.v, b.v)};
}
unsigned le_bits(V a, V b) {
  return static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ)));
}

}  // namespace
}  // namespace medspheres::check::detail

#include "kernel_body.h"

namespace medspheres::check::detail {

void run_block_avx2(const KernelRobot& robot, const SceneGrid& scene, Block& block) {
  run_block(robot, scene, block);
}

}  // namespace medspheres::check::detail
