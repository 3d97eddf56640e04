// The self-collision matrix and the default configuration (self_collision_matrix.h).
#include "medspheres/robot_bake/self_collision_matrix.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <numeric>
#include <set>

#include "contact_search.h"
#include "locked_samples.h"
#include "medspheres/error.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/number_text.h"
#include "medspheres/robot_bake/mirror_links.h"
#include "medspheres/thread_option.h"
#include "medspheres/threads.h"

namespace medspheres {

namespace {

using Poses = std::vector<Eigen::Isometry3d>;

// The configuration vector (KinematicTree order) of \p positions; joints it lacks at 0.
Eigen::VectorXd configuration(const KinematicTree& tree,
                              const std::map<std::string, double>& positions) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tree.num_positions()));
  for (std::size_t k = 0; k < tree.num_positions(); ++k) {
    const auto it = positions.find(tree.joint_names()[k]);
    if (it != positions.end()) q[static_cast<Eigen::Index>(k)] = it->second;
  }
  return q;
}

// What the samples showed of one pair; `done` once no further sample can change its class.
struct PairSeen {
  std::size_t hits = 0, misses = 0;               // samples where the solids touch / do not
  bool near = false;                              // the solids came within the margin
  bool spheres = false;                           // the planner's spheres touched
  std::size_t first_near = 0, first_spheres = 0;  // the samples where each was first seen
};

// Walks the samples for the pair (a, b) until its class is settled.
PairSeen sample_pair(const LinkSolids& solids, const PlannerSpheres& carried,
                     const std::vector<Poses>& poses, std::size_t a, std::size_t b,
                     const SelfCollisionOptions& o, SolidQueryCounts& counts,
                     std::size_t& sphere_tests) {
  PairSeen seen;
  // "always" is still possible while the misses stay within the rest of the threshold.
  const double max_misses = (1.0 - o.threshold) * static_cast<double>(poses.size());
  for (std::size_t s = 0; s < poses.size(); ++s) {
    const Poses& X = poses[s];
    const bool always_open = static_cast<double>(seen.misses) <= max_misses;
    const bool need_hit = always_open || seen.hits == 0;
    if (!need_hit && seen.near && seen.spheres) break;
    bool near = true;
    if (!seen.near || !need_hit) near = solids.within(X, a, b, o.margin, &counts);
    if (near && !seen.near) seen.first_near = s;
    seen.near = seen.near || near;
    if (need_hit) {
      const bool hit = near && solids.within(X, a, b, 0.0, &counts);
      ++(hit ? seen.hits : seen.misses);
    }
    if (!seen.spheres) {
      ++sphere_tests;
      seen.spheres = carried.collide(X, a, b);
      if (seen.spheres) seen.first_spheres = s;
    }
  }
  return seen;
}

PairClass sampled_class(const PairSeen& s, std::size_t samples, double threshold) {
  const bool all_counted = s.hits + s.misses == samples;
  if (all_counted && static_cast<double>(s.hits) >= threshold * static_cast<double>(samples))
    return PairClass::kAlways;
  if (!s.near) return PairClass::kNever;
  if (s.hits == 0 && s.spheres) return PairClass::kSphereOnly;
  return PairClass::kChecked;
}

// The checked pairs whose planner spheres touch at the poses X.
std::vector<std::size_t> touching(const std::vector<LinkPairClass>& pairs,
                                  const std::vector<std::pair<std::size_t, std::size_t>>& index,
                                  const PlannerSpheres& carried, const Poses& X) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (!pairs[k].ignored && carried.collide(X, index[k].first, index[k].second)) out.push_back(k);
  return out;
}

// The pairs of links with the planner's spheres, in model order, each with its links'
// indices; buffers 0.
std::vector<std::pair<std::size_t, std::size_t>> list_pairs(const RobotModel& model,
                                                            const PlannerSpheres& carried,
                                                            SelfCollisionMatrix& m) {
  std::vector<std::pair<std::size_t, std::size_t>> index;
  for (std::size_t a = 0; a < model.links.size(); ++a) {
    if (!carried.has(a)) continue;
    m.buffer[model.links[a].name] = 0.0;
    for (std::size_t b = a + 1; b < model.links.size(); ++b)
      if (carried.has(b)) {
        index.emplace_back(a, b);
        m.pairs.push_back(
            {model.links[a].name, model.links[b].name, PairClass::kChecked, false, ""});
      }
  }
  return index;
}

// The given pairs' reasons, by (link1, link2) in name order.
std::map<std::pair<std::string, std::string>, std::string> given_pairs(
    const RobotModel& model, const std::vector<formats::DisabledCollision>& given) {
  check_disabled_pairs(model, given);
  std::map<std::pair<std::string, std::string>, std::string> out;
  for (const formats::DisabledCollision& g : given) out[std::minmax(g.link1, g.link2)] = g.reason;
  return out;
}

// The matrix's samples: the configurations (the locked joints held) and every link's poses
// in each.
struct Sampled {
  const KinematicTree& tree;
  const std::map<std::string, double>& locked;
  std::vector<Eigen::VectorXd> qs;
  std::vector<Poses> poses;
};

// The two samples where the centres of the covering balls of links a and b come nearest (a
// pair that never came within the margin: where its search starts).
std::vector<Eigen::VectorXd> nearest_balls(const LinkSolids& solids, const Sampled& sampled,
                                           std::size_t a, std::size_t b) {
  const Sphere &ba = solids.ball(a), &bb = solids.ball(b);
  std::vector<std::pair<double, std::size_t>> gap;
  for (std::size_t s = 0; s < sampled.poses.size(); ++s) {
    const Poses& X = sampled.poses[s];
    gap.emplace_back((X[a] * ba.center - X[b] * bb.center).norm(), s);
  }
  const std::size_t n = std::min<std::size_t>(2, gap.size());
  std::partial_sort(gap.begin(), gap.begin() + static_cast<long>(n), gap.end());
  std::vector<Eigen::VectorXd> out;
  for (std::size_t k = 0; k < n; ++k) out.push_back(sampled.qs[gap[k].second]);
  return out;
}

// The search for a contact of a pair its samples would skip (\p kind never or sphere_only;
// file comment): from the samples where it first came near and first had its spheres touch,
// or where its links' balls came nearest.
std::optional<Eigen::VectorXd> search_skipped(const detail::ContactSearchRobot& r,
                                              const Sampled& sampled, const PairSeen& seen,
                                              PairClass kind, std::size_t a, std::size_t b,
                                              unsigned seed, SolidQueryCounts& counts) {
  const std::vector<Eigen::VectorXd> starts =
      kind == PairClass::kSphereOnly ? std::vector<Eigen::VectorXd>{sampled.qs[seen.first_spheres],
                                                                    sampled.qs[seen.first_near]}
                                     : nearest_balls(r.solids, sampled, a, b);
  return detail::search_contact(r, a, b, starts, seed, counts);
}

// Classifies every pair (file comment); the exact side's work into \p run.
void classify_pairs(const RobotModel& model, const LinkSolids& solids,
                    const PlannerSpheres& carried,
                    const std::vector<std::pair<std::size_t, std::size_t>>& index,
                    const Sampled& sampled, const std::vector<formats::DisabledCollision>& given,
                    const SelfCollisionOptions& o, SelfCollisionRun& run,
                    std::vector<char>& seen_colliding) {
  seen_colliding.assign(index.size(), 0);
  std::vector<bool> has(model.links.size());
  for (std::size_t i = 0; i < has.size(); ++i) has[i] = carried.has(i);
  const auto adjacent = adjacent_link_pairs(model, has);
  const auto given_reasons = given_pairs(model, given);
  const std::vector<std::size_t> body = rigid_bodies(model);
  std::vector<LinkPairClass>& pairs = run.matrix.pairs;
  const std::vector<Poses>& poses = sampled.poses;
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count(o.threads))
  for (std::size_t k = 0; k < index.size(); ++k) {
    const auto [a, b] = index[k];
    LinkPairClass& p = pairs[k];
    SolidQueryCounts counts;
    std::size_t tests = 0;
    const auto given_it = given_reasons.find(std::minmax(p.link1, p.link2));
    if (given_it != given_reasons.end()) {
      p.kind = PairClass::kGiven;
      p.reason = given_it->second;
    } else if (std::binary_search(adjacent.begin(), adjacent.end(), index[k])) {
      p.kind = PairClass::kAdjacent;
    } else if (!solids.has(a) || !solids.has(b)) {
      p.kind = PairClass::kChecked;  // no solid to judge by: the planner checks it
    } else if (body[a] == body[b]) {
      p.kind = solids.within(poses[0], a, b, o.margin, &counts) ? PairClass::kAdjacent
                                                                : PairClass::kNever;
    } else {
      const PairSeen seen = sample_pair(solids, carried, poses, a, b, o, counts, tests);
      p.kind = sampled_class(seen, poses.size(), o.threshold);
      seen_colliding[k] = seen.hits > 0;
      if (o.search && (p.kind == PairClass::kSphereOnly || p.kind == PairClass::kNever)) {
        const std::optional<Eigen::VectorXd> contact =
            search_skipped({model, sampled.tree, solids, carried, sampled.locked}, sampled, seen,
                           p.kind, a, b, o.seed + static_cast<unsigned>(k), counts);
        if (contact) {
          p.kind = PairClass::kChecked;
          seen_colliding[k] = 1;
#pragma omp critical(self_collision_contacts)
          run.contacts[{p.link1, p.link2}] = *contact;
        }
      }
    }
    p.ignored = p.kind != PairClass::kChecked;
#pragma omp critical(self_collision_counts)
    {
      run.solids += counts;
      run.sphere_tests += tests;
    }
  }
}

// The pairs skipped as never or sphere_only whose mirror image (mirror_links.h) was seen
// colliding and is checked: checked too, as the samples missed a contact its twin shows.
void check_mirror_images(const RobotModel& model,
                         const std::vector<std::pair<std::size_t, std::size_t>>& index,
                         const std::vector<char>& seen_colliding, SelfCollisionRun& run) {
  const std::vector<std::size_t> image = mirror_links(model);
  if (image.empty()) return;
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> position;
  for (std::size_t k = 0; k < index.size(); ++k) position[index[k]] = k;
  std::vector<LinkPairClass>& pairs = run.matrix.pairs;
  for (std::size_t k = 0; k < index.size(); ++k) {
    if (pairs[k].kind != PairClass::kNever && pairs[k].kind != PairClass::kSphereOnly) continue;
    const auto it = position.find(std::minmax(image[index[k].first], image[index[k].second]));
    if (it == position.end() || !seen_colliding[it->second] ||
        pairs[it->second].kind != PairClass::kChecked)
      continue;
    pairs[k].kind = PairClass::kChecked;
    pairs[k].ignored = false;
    ++run.mirrored;
  }
}

// The default configuration (file comment), and the checked pairs colliding at the zero
// pose marked "default".
void choose_default(const RobotModel& model, const KinematicTree& tree, const LinkSolids& solids,
                    const PlannerSpheres& carried,
                    const std::vector<std::pair<std::size_t, std::size_t>>& index,
                    const std::vector<Eigen::VectorXd>& qs, const std::vector<Poses>& poses,
                    const std::map<std::string, double>& locked, SelfCollisionRun& run) {
  std::map<std::string, double> zero = clamped_zero(model);
  for (const auto& [joint, q] : locked) zero[joint] = q;
  const Eigen::VectorXd q0 = configuration(tree, zero);
  const Poses X0 = tree.link_poses(q0);
  std::vector<LinkPairClass>& pairs = run.matrix.pairs;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [a, b] = index[k];
    if (!pairs[k].ignored && solids.has(a) && solids.has(b) && solids.within(X0, a, b, 0.0))
      pairs[k].kind = PairClass::kDefault;
  }
  run.default_positions = zero;
  run.default_from = "zero";
  const std::vector<std::size_t> at_zero = touching(pairs, index, carried, X0);
  if (at_zero.empty()) return;
  // Candidates: each sample, and the points 1/16, 1/8, 1/4 and 1/2 of the way to it from
  // the zero pose; nearest first.
  static constexpr double kSteps[] = {1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0 / 2, 1.0};
  struct Candidate {
    double distance;
    std::size_t sample, step;
  };
  std::vector<Candidate> candidates;
  for (std::size_t s = 0; s < qs.size(); ++s)
    for (std::size_t k = 0; k < std::size(kSteps); ++k)
      candidates.push_back({kSteps[k] * (qs[s] - q0).norm(), s, k});
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.distance < y.distance; });
  for (const Candidate& c : candidates) {
    const double t = kSteps[c.step];
    const Eigen::VectorXd q =
        t == 1.0 ? qs[c.sample] : Eigen::VectorXd(q0 + t * (qs[c.sample] - q0));
    if (!touching(pairs, index, carried, t == 1.0 ? poses[c.sample] : tree.link_poses(q)).empty())
      continue;
    for (std::size_t k = 0; k < tree.num_positions(); ++k)
      run.default_positions[tree.joint_names()[k]] = q[static_cast<Eigen::Index>(k)];
    run.default_from = "sample";
    return;
  }
  // No free configuration found: shrink the spheres of each link of a pair touching at the
  // zero pose, for self-collision only, by half that pair's deepest overlap and 0.1 mm.
  std::map<std::string, double>& buffer = run.matrix.buffer;
  for (std::size_t k : at_zero) {
    const double shrink = carried.penetration(X0, index[k].first, index[k].second) / 2 + 1e-4;
    for (const std::string* link : {&pairs[k].link1, &pairs[k].link2})
      buffer[*link] = std::min(buffer[*link], -shrink);
  }
  const std::vector<std::size_t> left = touching(pairs, index, carried.with_buffer(buffer), X0);
  run.default_from = left.empty() ? "zero_buffered" : "zero_not_free";
  for (std::size_t k : left) run.default_pairs.emplace_back(pairs[k].link1, pairs[k].link2);
}

[[noreturn]] void bad_option(const char* field, const std::string& value, const std::string& why) {
  throw InputError::option(ErrorKind::kOutOfRange, field, value, why);
}

}  // namespace

void check_disabled_pairs(const RobotModel& model,
                          const std::vector<formats::DisabledCollision>& given) {
  for (const formats::DisabledCollision& g : given)
    for (const std::string* l : {&g.link1, &g.link2})
      if (!model.find_link(*l))
        throw InputError::option(ErrorKind::kOutOfRange, "srdf", *l,
                                 "the disabled pair (\"" + g.link1 + "\", \"" + g.link2 +
                                     "\") names \"" + *l + "\", no link of the robot");
}

void validate(const SelfCollisionOptions& o) {
  if (o.samples < 1) bad_option("self_collision_samples", "0", "must be at least 1");
  if (!(o.threshold > 0.0 && o.threshold <= 1.0))
    bad_option("self_collision_threshold", number_text(o.threshold), "must be in (0, 1]");
  if (!std::isfinite(o.margin) || o.margin < 0.0)
    bad_option("self_collision_margin", number_text(o.margin), "must be finite and >= 0 (metres)");
  check_threads_option(o.threads, "threads");
}

SelfCollisionRun compute_self_collision(const RobotModel& model, const LinkSolids& solids,
                                        const formats::RobotSpheres& carried_spheres,
                                        const std::map<std::string, double>& locked,
                                        const std::vector<formats::DisabledCollision>& given,
                                        const SelfCollisionOptions& o) {
  validate(o);
  const auto t0 = std::chrono::steady_clock::now();
  const KinematicTree tree(model);
  const PlannerSpheres carried(model, carried_spheres);
  SelfCollisionRun run;
  run.matrix.samples = o.samples;
  run.matrix.seed = o.seed;
  run.matrix.threshold = o.threshold;
  run.matrix.margin = o.margin;
  const auto index = list_pairs(model, carried, run.matrix);
  Sampled sampled{tree, locked, detail::locked_samples(model, tree, locked, o.samples, o.seed), {}};
  const std::vector<Eigen::VectorXd>& qs = sampled.qs;
  std::vector<Poses>& poses = sampled.poses;
  poses.resize(qs.size());
#pragma omp parallel for schedule(static) num_threads(thread_count(o.threads))
  for (std::size_t s = 0; s < qs.size(); ++s) poses[s] = tree.link_poses(qs[s]);
  std::vector<char> seen_colliding;
  classify_pairs(model, solids, carried, index, sampled, given, o, run, seen_colliding);
  check_mirror_images(model, index, seen_colliding, run);
  choose_default(model, tree, solids, carried, index, qs, poses, locked, run);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

}  // namespace medspheres
