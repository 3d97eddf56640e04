// The planner files' self-collision checks against the solids (self_collision_estimate.h).
#include "medspheres/robot_bake/self_collision_estimate.h"

#include <algorithm>
#include <cstdint>

#include "locked_samples.h"
#include "medspheres/error.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/threads.h"

namespace medspheres {

namespace {

using Poses = std::vector<Eigen::Isometry3d>;
using Pair = std::pair<std::size_t, std::size_t>;  // links' indices, model order

// The matrix's pairs as link indices: the checked ones and the judged ones (file comment).
struct JudgedPairs {
  std::vector<std::size_t> checked, judged;  // indices into the matrix's pairs
  std::vector<Pair> links;                   // per matrix pair
};

JudgedPairs judged_pairs(const RobotModel& model, const KinematicTree& tree,
                         const LinkSolids& solids, const SelfCollisionMatrix& matrix) {
  JudgedPairs out;
  for (std::size_t k = 0; k < matrix.pairs.size(); ++k) {
    const LinkPairClass& p = matrix.pairs[k];
    for (const std::string* name : {&p.link1, &p.link2})
      if (!model.find_link(*name))
        throw InputError::option(ErrorKind::kOutOfRange, "self_collision", *name,
                                 "the matrix's pair (\"" + p.link1 + "\", \"" + p.link2 +
                                     "\") names \"" + *name + "\", no link of the robot");
    const Pair link{tree.link_index(p.link1), tree.link_index(p.link2)};
    out.links.push_back(link);
    if (!p.ignored) out.checked.push_back(k);
    if (p.kind != PairClass::kAdjacent && p.kind != PairClass::kAlways && solids.has(link.first) &&
        solids.has(link.second))
      out.judged.push_back(k);
  }
  return out;
}

// One configuration's verdicts: 1 a false positive, -1 a false negative, 0 neither; `alone`
// the matrix pair whose spheres alone touch in a false positive (else none).
struct Verdict {
  int kind = 0;
  std::size_t alone = SIZE_MAX;
};

Verdict judge(const JudgedPairs& p, const LinkSolids& solids, const PlannerSpheres& spheres,
              const Poses& X) {
  std::size_t touching = 0, first = SIZE_MAX;
  for (std::size_t k : p.checked)
    if (spheres.collide(X, p.links[k].first, p.links[k].second) && ++touching == 1) first = k;
  const auto solid = [&](std::size_t k) {
    return solids.has(p.links[k].first) && solids.has(p.links[k].second) &&
           solids.within(X, p.links[k].first, p.links[k].second, 0.0);
  };
  Verdict v;
  if (touching > 0) {
    if (std::none_of(p.judged.begin(), p.judged.end(), solid))
      v = {1, touching == 1 ? first : SIZE_MAX};
  } else if (std::any_of(p.checked.begin(), p.checked.end(), solid)) {
    v.kind = -1;
  }
  return v;
}

}  // namespace

SelfCollisionEstimate estimate_self_collision(const RobotModel& model, const LinkSolids& solids,
                                              const formats::RobotSpheres& carried,
                                              const SelfCollisionMatrix& matrix,
                                              const std::map<std::string, double>& locked,
                                              std::size_t samples, unsigned seed, int threads) {
  const KinematicTree tree(model);
  const PlannerSpheres spheres(model, carried, matrix.buffer);
  const JudgedPairs pairs = judged_pairs(model, tree, solids, matrix);
  const std::vector<Eigen::VectorXd> qs =
      detail::locked_samples(model, tree, locked, samples, seed);
  std::vector<Verdict> verdicts(qs.size());
#pragma omp parallel for schedule(dynamic, 16) num_threads(thread_count(threads))
  for (std::size_t s = 0; s < qs.size(); ++s)
    verdicts[s] = judge(pairs, solids, spheres, tree.link_poses(qs[s]));
  SelfCollisionEstimate e;
  e.samples = samples;
  e.seed = seed;
  std::vector<std::size_t> alone(matrix.pairs.size(), 0);
  for (const Verdict& v : verdicts) {
    e.false_positives += v.kind == 1;
    e.false_negatives += v.kind == -1;
    if (v.alone != SIZE_MAX) ++alone[v.alone];
  }
  for (std::size_t k = 0; k < alone.size(); ++k)
    if (alone[k] > 0) e.alone.push_back({{matrix.pairs[k].link1, matrix.pairs[k].link2}, alone[k]});
  std::stable_sort(e.alone.begin(), e.alone.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  return e;
}

}  // namespace medspheres
