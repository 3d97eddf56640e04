#pragma once
// bench_checker --fallback-report: where the certified checker's fallback goes. For every
// configuration the bounds leave undecided, the steps of CertifiedChecker's fallback one by
// one (the bounds again with their undecided pairs, the links' poses, decide() on each pair
// by the links' sphere trees, settle() by the exact meshes), each timed, and per pair of
// links (or link and scene object) how often it is undecided, what decided it, how long that
// took, and how far apart the meshes were when they settled it free (FCL's distance,
// not pruned at the margin: the 10th and 50th percentiles). A pair of a link and an
// octree is settled twice: by FCL's octree query (`mesh us`) and by the checker's
// OctreeCells (`cells us`); the report counts where their verdicts differ.

#include "medspheres/fcl/certified_checker.h"
#include "robot_bench_check.h"

namespace medspheres::bench {

void print_fallback_report(const CheckerBenchInput& in, const fcl::CertifiedChecker& certified);

}  // namespace medspheres::bench
