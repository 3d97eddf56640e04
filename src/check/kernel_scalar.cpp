// The kernel with a plain lane type: four doubles, one operation each (the path for
// machines without AVX2, and the reference the AVX2 path must match bit for bit).

#include "block.h"

namespace medspheres::check::detail {
namespace {

struct V {
  double v[kLanes];
};

V splat(double a) {
  V r;
  for (double& x : r.v) x = a;
  return r;
}
V load(const double* p) {
  V r;
  for (int l = 0; l < kLanes; ++l) r.v[l] = p[l];
  return r;
}
void store(double* p, V a) {
  for (int l = 0; l < kLanes; ++l) p[l] = a.v[l];
}
V operator+(V a, V b) {
  for (int l = 0; l < kLanes; ++l) a.v[l] += b.v[l];
  return a;
}
V operator-(V a, V b) {
  for (int l = 0; l < kLanes; ++l) a.v[l] -= b.v[l];
  return a;
}
V operator*(V a, V b) {
  for (int l = 0; l < kLanes; ++l) a.v[l] *= b.v[l];
  return a;
}
unsigned le_bits(V a, V b) {
  unsigned m = 0;
  for (int l = 0; l < kLanes; ++l) m |= (a.v[l] <= b.v[l] ? 1u : 0u) << l;
  return m;
}

}  // namespace
}  // namespace medspheres::check::detail

#include "kernel_body.h"

namespace medspheres::check::detail {

void run_block_scalar(const KernelRobot& robot, const SceneGrid& scene, Block& block) {
  run_block(robot, scene, block);
}

}  // namespace medspheres::check::detail
