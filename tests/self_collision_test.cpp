// The self-collision matrix on generated arms: every pair's class against a brute-force
// oracle over the same samples (FCL's exact distance on each meshed part and sphere
// primitive, winding numbers for containment, every sphere pair of the planner's set), no
// false negatives over other samples, a free default configuration, the same matrix for
// any number of threads, SRDF pairs and end effectors taken as given; and on the G1.
#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/distance.h>
#include <catch2/catch.hpp>

#include "medspheres/error.h"
#include "medspheres/fcl/robot_bounds.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/mesh/mesh_query.h"
#include "medspheres/robot_bake/mirror_links.h"
#include "medspheres/robot_bake/robot_bake.h"
#include "medspheres/robot_bake/robot_planner_setup.h"
#include "medspheres/robot_bake/self_collision_estimate.h"
#include "support/generated_arms.h"
#include "support/robot_fixtures.h"
#include "support/sanitizer_build.h"
#include "support/temp_dir.h"

using Catch::Matchers::Contains;
using namespace medspheres;
using medspheres::test::TempDir;

namespace {

using Poses = std::vector<Eigen::Isometry3d>;
using Names = std::vector<std::string>;

struct BakedRobot {
  RobotModel model;
  std::vector<LinkSolid> solids;
};

BakedRobot bake(const std::string& urdf, std::size_t per_link) {
  const UrdfRobot robot = read_urdf(urdf);
  BakedRobot out;
  out.solids = load_link_solids(robot);
  RobotBakeOptions o;
  o.budget.per_link = per_link;
  o.request.measure = false;
  o.jobs = 2;
  out.model = bake_robot(robot, out.solids, o).model;
  return out;
}

BakedRobot generated_arm(const TempDir& dir, unsigned seed, bool mimic) {
  // 4 spheres a link in the sanitizer builds, where the bake takes most of the tests' time.
  return bake(
      dir.write("arm" + std::to_string(seed) + ".urdf", test::generated_arm_urdf(seed, 5, mimic)),
      test::kSanitizerBuild ? 4 : 8);
}

// The oracle's view of one link: FCL objects for its meshed parts (one mesh) and sphere
// primitives, and the mesh's solid for containment.
struct ExactLink {
  std::vector<std::shared_ptr<::fcl::CollisionGeometryd>> parts;
  std::shared_ptr<MeshQuery> solid;
};

std::vector<ExactLink> exact_links(const RobotModel& m, const std::vector<LinkSolid>& solids) {
  std::vector<ExactLink> out(m.links.size());
  for (const LinkSolid& s : solids) {
    std::size_t i = 0;
    while (m.links[i].name != s.link) ++i;
    if (!s.parts.empty()) {
      const TriangleMesh mesh = s.placed_mesh();
      out[i].parts.push_back(std::const_pointer_cast<medspheres::fcl::MeshModel>(
          medspheres::fcl::make_mesh_model(mesh)));
      out[i].solid = std::make_shared<MeshQuery>(mesh);
    }
    for (const Sphere& b : s.spheres)  // placed at its centre by exact_distance
      out[i].parts.push_back(std::make_shared<::fcl::Sphered>(b.radius));
  }
  return out;
}

// The sphere primitives' centres in the link frame, in the parts' order after the mesh.
std::vector<Eigen::Vector3d> primitive_centres(const LinkSolid& s) {
  std::vector<Eigen::Vector3d> out;
  for (const Sphere& b : s.spheres) out.push_back(b.center);
  return out;
}

// The exact distance of links a and b at the poses X, clamped to 0 when they overlap: the
// least FCL distance over their parts, 0 when a vertex of one lies in the other's meshed
// solid (containment, which a distance between surfaces misses).
double exact_distance(const std::vector<ExactLink>& e, const std::vector<LinkSolid>& solids,
                      const RobotModel& m, const Poses& X, std::size_t a, std::size_t b) {
  const auto part_pose = [&](std::size_t link, std::size_t k) {
    const bool has_mesh = e[link].solid != nullptr;
    if (has_mesh && k == 0) return X[link];
    const LinkSolid* s = nullptr;
    for (const LinkSolid& t : solids)
      if (t.link == m.links[link].name) s = &t;
    Eigen::Isometry3d p = X[link];
    p.translate(primitive_centres(*s)[k - (has_mesh ? 1 : 0)]);
    return p;
  };
  double d = 1e9;
  for (std::size_t i = 0; i < e[a].parts.size(); ++i)
    for (std::size_t j = 0; j < e[b].parts.size(); ++j) {
      ::fcl::DistanceRequestd request;
      ::fcl::DistanceResultd result;
      d = std::min(d, ::fcl::distance(e[a].parts[i].get(), part_pose(a, i), e[b].parts[j].get(),
                                      part_pose(b, j), request, result));
    }
  for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, a}})
    if (e[q].solid && d > 0)
      for (const LinkSolid& s : solids)
        if (s.link == m.links[p].name && !s.parts.empty())
          for (const Eigen::Vector3d& v : s.placed_mesh().vertices)
            if (e[q].solid->winding_number(X[q].inverse() * (X[p] * v)) > 0.5) return 0.0;
  return std::max(d, 0.0);
}

// Two spheres of the sets touch, with \p grow added to the sum of their radii (cuRobo's
// self-collision buffers of the two links), every pair tried.
bool spheres_touch(const std::vector<Sphere>& a, const Eigen::Isometry3d& Xa,
                   const std::vector<Sphere>& b, const Eigen::Isometry3d& Xb, double grow = 0.0) {
  for (const Sphere& s : a)
    for (const Sphere& t : b)
      if ((Xa * s.center - Xb * t.center).norm() <= s.radius + t.radius + grow) return true;
  return false;
}

// The planner's check of a pair at the poses X: the covering sets with the matrix's buffers.
bool planner_touch(const RobotModel& m, const SelfCollisionMatrix& mx, const Poses& X,
                   std::size_t a, std::size_t b) {
  const double grow = mx.buffer.at(m.links[a].name) + mx.buffer.at(m.links[b].name);
  return spheres_touch(m.links[a].spheres.outer.spheres, X[a], m.links[b].spheres.outer.spheres,
                       X[b], grow);
}

std::size_t link_index(const RobotModel& m, const std::string& name) {
  for (std::size_t i = 0; i < m.links.size(); ++i)
    if (m.links[i].name == name) return i;
  FAIL("no link " << name);
  return 0;
}

std::vector<Poses> posed(const RobotModel& m, const std::map<std::string, double>& locked,
                         std::size_t n, unsigned seed) {
  const KinematicTree tree(m);
  std::vector<Poses> out;
  for (Eigen::VectorXd q : medspheres::fcl::sample_configurations(m, tree, n, seed)) {
    for (std::size_t k = 0; k < tree.num_positions(); ++k) {
      const auto it = locked.find(tree.joint_names()[k]);
      if (it != locked.end()) q[static_cast<Eigen::Index>(k)] = it->second;
    }
    out.push_back(tree.link_poses(q));
  }
  return out;
}

// The class the matrix's rules give a sampled pair (self_collision_matrix.h), from the
// oracle's distances over the samples.
PairClass expected_class(const std::vector<double>& d, const std::vector<bool>& spheres,
                         const SelfCollisionOptions& o, std::size_t& hits) {
  hits = 0;
  bool near = false, touched = false;
  for (std::size_t s = 0; s < d.size(); ++s) {
    hits += d[s] <= 0.0;
    near = near || d[s] <= o.margin;
    touched = touched || spheres[s];
  }
  if (static_cast<double>(hits) >= o.threshold * static_cast<double>(d.size()))
    return PairClass::kAlways;
  if (!near) return PairClass::kNever;
  if (hits == 0 && touched) return PairClass::kSphereOnly;
  return PairClass::kChecked;
}

// The name with "left" and "right" exchanged (the generated arms' fingers).
std::string other_side(std::string name) {
  for (const auto& [from, to] : {std::pair{"left", "right"}, std::pair{"right", "left"}})
    if (name.rfind(from, 0) == 0) return to + name.substr(std::string(from).size());
  return name;
}

}  // namespace

TEST_CASE("self-collision matrix of generated arms: brute force agrees, free default, no miss",
          "[robot][self_collision]") {
  std::size_t contacts = 0;      // checked pairs' solids touching, over both arms
  std::size_t all_mirrored = 0;  // pairs checked as their mirror images, over both arms
  std::size_t all_searched = 0;  // pairs checked by a contact searched for, over both arms
  // The second arm once more without the search for contacts, where the mirror rule has
  // pairs of its own; each arm is baked once.
  struct Case {
    unsigned seed;
    bool mimic, search;
  };
  TempDir dir;
  std::map<unsigned, BakedRobot> arms;
  for (const auto& [seed, mimic, search] :
       {Case{3, false, true}, Case{4, true, true}, Case{4, true, false}}) {
    INFO("arm " << seed << (search ? "" : ", no search"));
    if (!arms.count(seed)) arms.emplace(seed, generated_arm(dir, seed, mimic));
    const BakedRobot& r = arms.at(seed);
    PlannerRequest request;
    request.self_collision.samples = 300;
    request.self_collision.seed = seed;
    request.self_collision.search = search;
    SelfCollisionRun run;
    const PlannerSetup s =
        make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request, &run);
    // Tool frames: the hand carries the fingers; the sensor ends the other branch.
    CHECK(s.tool_frames == Names{"hand", "sensor"});
    CHECK(s.tool_frames_from == "gripper");
    CHECK(s.locked_joints ==
          (mimic ? Names{"left_finger_joint"} : Names{"left_finger_joint", "right_finger_joint"}));
    REQUIRE(s.self_collision);
    const SelfCollisionMatrix& m = *s.self_collision;
    // Every pair of links with spheres once: 9 links (base, 5 arm links, hand, fingers).
    REQUIRE(m.pairs.size() == 9 * 8 / 2);
    std::map<std::string, double> locked;
    for (const std::string& j : s.locked_joints) locked[j] = s.default_positions.at(j);
    const std::vector<Poses> samples = posed(r.model, locked, 300, seed);
    const std::vector<ExactLink> exact = exact_links(r.model, r.solids);
    // The rules' class of every sampled pair, and whether its solids touched in a sample.
    std::map<std::pair<std::string, std::string>, std::pair<PairClass, bool>> oracle;
    for (const LinkPairClass& p : m.pairs) {
      if (p.kind == PairClass::kAdjacent) continue;
      const std::size_t a = link_index(r.model, p.link1), b = link_index(r.model, p.link2);
      std::vector<double> d;
      std::vector<bool> touch;
      for (const Poses& X : samples) {
        d.push_back(exact_distance(exact, r.solids, r.model, X, a, b));
        touch.push_back(spheres_touch(r.model.links[a].spheres.outer.spheres, X[a],
                                      r.model.links[b].spheres.outer.spheres, X[b]));
      }
      std::size_t hits = 0;
      const PairClass c = expected_class(d, touch, request.self_collision, hits);
      oracle[std::minmax(p.link1, p.link2)] = {c, hits > 0};
    }
    // A pair the search found touching: never or sphere_only by its samples, its solids touch at
    // the configuration found (the oracle's own distance; the search stops at the first pose
    // its certified test calls touching, at the contact's edge, where FCL's distance is 0 up
    // to its rounding).
    const KinematicTree tree(r.model);
    for (const auto& [names, q] : run.contacts) {
      INFO(names.first << " " << names.second);
      auto& [kind, hit] = oracle.at(std::minmax(names.first, names.second));
      CHECK((kind == PairClass::kSphereOnly || kind == PairClass::kNever));
      CHECK(exact_distance(exact, r.solids, r.model, tree.link_poses(q),
                           link_index(r.model, names.first),
                           link_index(r.model, names.second)) <= 1e-9);
      kind = PairClass::kChecked;
      hit = true;
      ++all_searched;
    }
    std::map<PairClass, int> seen;
    std::size_t mirrored = 0;
    for (const LinkPairClass& p : m.pairs) {
      INFO(p.link1 << " " << p.link2 << " " << pair_class_name(p.kind));
      ++seen[p.kind];
      if (p.kind == PairClass::kAdjacent) {
        // Joined by a joint; link5 and the hand are one rigid body, touching.
        static const std::set<std::pair<std::string, std::string>> adjacent = {
            {"base", "link1"},       {"link1", "link2"},      {"link2", "link3"},
            {"link3", "link4"},      {"link4", "link5"},      {"link5", "hand"},
            {"hand", "left_finger"}, {"hand", "right_finger"}};
        CHECK(adjacent.count({p.link1, p.link2}) == 1);
        continue;
      }
      PairClass want = oracle.at(std::minmax(p.link1, p.link2)).first;
      // Skipped by its samples, checked as its mirror image (the fingers exchanged) is
      // checked and was seen touching.
      const auto image = oracle.find(std::minmax(other_side(p.link1), other_side(p.link2)));
      if ((want == PairClass::kNever || want == PairClass::kSphereOnly) && image != oracle.end() &&
          image->second == std::pair{PairClass::kChecked, true}) {
        want = PairClass::kChecked;
        ++mirrored;
      }
      if (p.kind == PairClass::kDefault)
        CHECK(want == PairClass::kChecked);
      else
        CHECK(p.kind == want);
      CHECK(p.ignored == (p.kind != PairClass::kChecked && p.kind != PairClass::kDefault));
    }
    CHECK(run.mirrored == mirrored);
    all_mirrored += mirrored;
    CHECK(seen[PairClass::kAdjacent] == 8);
    CHECK(seen[PairClass::kChecked] + seen[PairClass::kDefault] > 0);
    CHECK(seen[PairClass::kNever] > 0);

    // The default configuration: no checked pair's spheres touch there, without buffers.
    const Poses X0 = tree.link_poses(s.default_positions);
    CHECK((s.default_from == "zero" || s.default_from == "sample"));
    for (const auto& [link, b] : m.buffer) CHECK(b == 0.0);
    for (const LinkPairClass& p : m.pairs) {
      if (p.ignored) continue;
      const std::size_t a = link_index(r.model, p.link1), b = link_index(r.model, p.link2);
      INFO(p.link1 << " " << p.link2);
      CHECK(!planner_touch(r.model, m, X0, a, b));
    }
    // No false negative over other samples: where a checked pair's solids touch, so do its
    // covering spheres.
    for (const Poses& X : posed(r.model, locked, 300, seed + 1000))
      for (const LinkPairClass& p : m.pairs) {
        if (p.ignored) continue;
        const std::size_t a = link_index(r.model, p.link1), b = link_index(r.model, p.link2);
        if (exact_distance(exact, r.solids, r.model, X, a, b) > 0.0) continue;
        ++contacts;
        INFO(p.link1 << " " << p.link2);
        CHECK(planner_touch(r.model, m, X, a, b));
      }
  }
  CHECK(contacts > 0);
  CHECK(all_mirrored > 0);  // the rule ran: a finger pair its own samples missed
  CHECK(all_searched > 0);  // the search ran and found contacts
}

TEST_CASE("mirror images: sides swapped by name, the tree checked", "[robot][self_collision]") {
  CHECK(swap_side("left_hip_roll_link") == "right_hip_roll_link");
  CHECK(swap_side("RightArm_Left") == "LeftArm_Right");  // every one, each case apart
  CHECK(swap_side("l_gripper") == "r_gripper");
  CHECK(swap_side("finger_R") == "finger_L");
  CHECK(swap_side("arm_l_upper") == "arm_r_upper");
  CHECK(swap_side("torso_link") == std::nullopt);
  CHECK(swap_side("wheel") == std::nullopt);
  // A body with two arms of two joints: the images of a link and its joint.
  const auto two_arms = [](double right_offset) {
    RobotModel m;
    m.name = "two";
    m.root_link = "body";
    m.links.push_back(test::make_link("body"));
    for (const std::string side : {"left", "right"}) {
      const double y = side == "left" ? 0.2 : -right_offset;
      std::string parent = "body";
      for (const std::string part : {"_upper", "_lower"}) {
        m.links.push_back(test::make_link(side + part));
        m.joints.push_back(test::make_joint(side + part + "_joint", JointType::kRevolute, parent,
                                            side + part, {0, part == "_upper" ? y : 0.0, 0.3}));
        m.joints.back().limits = JointLimits{-1, 1, 1, 1};
        parent = side + part;
      }
    }
    return m;
  };
  CHECK(mirror_links(two_arms(0.2)) == std::vector<std::size_t>{0, 3, 4, 1, 2});
  // Within 1 mm an offset is the same; 2 mm apart, the tree is not its own image.
  CHECK(mirror_links(two_arms(0.2005)).size() == 5);
  CHECK(mirror_links(two_arms(0.202)).empty());
  RobotModel ranges = two_arms(0.2);
  ranges.joints.back().limits = JointLimits{-1, 2, 1, 1};
  CHECK(mirror_links(ranges).empty());
  RobotModel lone = two_arms(0.2);
  lone.links[4].name = lone.joints[3].child = "right_hand";  // "left_hand" is no link
  CHECK(mirror_links(lone).empty());
  RobotModel plain;
  plain.links.push_back(test::make_link("base"));
  CHECK(mirror_links(plain).empty());  // nothing sided
}

TEST_CASE("self-collision matrix: the same for 1 and 2 threads", "[robot][self_collision]") {
  TempDir dir;
  const BakedRobot r = generated_arm(dir, 5, false);
  PlannerRequest request;
  request.self_collision.samples = 300;
  std::vector<PlannerSetup> setups;
  for (int threads : {1, 2}) {
    request.self_collision.threads = threads;
    setups.push_back(make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request));
  }
  const auto& a = setups[0].self_collision->pairs;
  const auto& b = setups[1].self_collision->pairs;
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    CHECK(a[k].kind == b[k].kind);
    CHECK(a[k].ignored == b[k].ignored);
  }
  CHECK(setups[0].default_positions == setups[1].default_positions);
}

namespace {

// The estimate by brute force (self_collision_estimate.h): every judged pair's solids
// (solid[s][k]: the matrix's pair k touches in configuration s) and every sphere pair of
// every checked pair, with \p mx's buffers.
SelfCollisionEstimate brute_estimate(const RobotModel& model, const SelfCollisionMatrix& mx,
                                     const std::vector<Poses>& poses,
                                     const std::vector<std::vector<char>>& solid) {
  SelfCollisionEstimate e;
  std::map<std::pair<std::string, std::string>, std::size_t> alone;
  for (std::size_t s = 0; s < poses.size(); ++s) {
    std::vector<std::size_t> touching;
    bool any_solid = false, checked_solid = false;
    for (std::size_t k = 0; k < mx.pairs.size(); ++k) {
      const LinkPairClass& p = mx.pairs[k];
      any_solid = any_solid || solid[s][k];
      if (p.ignored) continue;
      checked_solid = checked_solid || solid[s][k];
      if (planner_touch(model, mx, poses[s], link_index(model, p.link1),
                        link_index(model, p.link2)))
        touching.push_back(k);
    }
    if (!touching.empty() && !any_solid) {
      ++e.false_positives;
      if (touching.size() == 1) ++alone[{mx.pairs[touching[0]].link1, mx.pairs[touching[0]].link2}];
    }
    e.false_negatives += touching.empty() && checked_solid;
  }
  for (const auto& [pair, n] : alone) e.alone.push_back({pair, n});
  return e;
}

std::map<std::pair<std::string, std::string>, std::size_t> alone_map(
    const SelfCollisionEstimate& e) {
  return {e.alone.begin(), e.alone.end()};
}

}  // namespace

TEST_CASE("self-collision estimate: brute force agrees, 1 and 2 threads, shrunk spheres miss",
          "[robot][self_collision]") {
  TempDir dir;
  const BakedRobot r = generated_arm(dir, 3, false);
  PlannerRequest request;
  request.self_collision.samples = 300;
  request.self_collision.seed = 3;
  request.self_collision.estimate = 400;
  SelfCollisionRun run;
  const PlannerSetup s =
      make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request, &run);
  const SelfCollisionMatrix& m = *s.self_collision;
  const SelfCollisionEstimate& e = run.estimate;
  CHECK(e.samples == 400);
  CHECK(e.seed == 3 + 7919);
  std::map<std::string, double> locked;
  for (const std::string& j : s.locked_joints) locked[j] = s.default_positions.at(j);
  // The oracle's configurations, drawn as the estimate draws its own.
  const std::vector<Poses> poses = posed(r.model, locked, 400, 3 + 7919);
  const std::vector<ExactLink> exact = exact_links(r.model, r.solids);
  // Two truths per judged pair: the exact distance (the oracle's own geometry) within 1e-9 m
  // (FCL's distance of two meshes in contact is not always 0 to the last bit: a subnormal at
  // times), and LinkSolids' certified test, which the estimate uses: it takes a sphere
  // primitive of a meshed link as an icosphere that contains it, so it may call touching a
  // pair a little apart. The estimate must equal the count over LinkSolids' truth (the
  // brute force: every pair, every sphere pair), and differ from the exact count by no more
  // than the configurations in which some pair lies within 2 mm without touching.
  const LinkSolids solids(r.model, r.solids);
  std::vector<std::vector<char>> exact_solid(poses.size()), certified(poses.size());
  std::size_t borderline = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    bool near = false;
    for (const LinkPairClass& p : m.pairs) {
      const std::size_t a = link_index(r.model, p.link1), b = link_index(r.model, p.link2);
      const bool judged = p.kind != PairClass::kAdjacent && p.kind != PairClass::kAlways;
      const double d = judged ? exact_distance(exact, r.solids, r.model, poses[i], a, b) : 1.0;
      exact_solid[i].push_back(d <= 1e-9);
      near = near || (d > 1e-9 && d <= 0.002);
      certified[i].push_back(judged && solids.within(poses[i], a, b, 0.0));
    }
    borderline += near;
  }
  CHECK(borderline <= poses.size() / 20);
  const auto differ = [](std::size_t x, std::size_t y) { return x > y ? x - y : y - x; };
  const SelfCollisionEstimate want = brute_estimate(r.model, m, poses, certified);
  CHECK(e.false_positives == want.false_positives);
  CHECK(e.false_negatives == 0);  // covering sets
  CHECK(want.false_negatives == 0);
  CHECK(alone_map(e) == alone_map(want));
  for (std::size_t k = 1; k < e.alone.size(); ++k)
    CHECK(e.alone[k - 1].second >= e.alone[k].second);
  CHECK(e.false_positives > 0);  // the covers stick out: a count that can be wrong
  const SelfCollisionEstimate exact_count = brute_estimate(r.model, m, poses, exact_solid);
  CHECK(differ(e.false_positives, exact_count.false_positives) <= borderline);
  CHECK(exact_count.false_negatives == 0);
  // Every link's spheres shrunk by 1 cm for self-collision (no longer covers): they miss
  // contacts, and the estimate counts them as the brute force does, on 1 and 2 threads.
  SelfCollisionMatrix shrunk = m;
  for (auto& [link, b] : shrunk.buffer) b = -0.01;
  const SelfCollisionEstimate want_shrunk = brute_estimate(r.model, shrunk, poses, certified);
  CHECK(want_shrunk.false_negatives > 0);
  CHECK(differ(want_shrunk.false_negatives,
               brute_estimate(r.model, shrunk, poses, exact_solid).false_negatives) <= borderline);
  const formats::RobotSpheres carried =
      formats::robot_spheres(r.model, formats::SphereChoice::kOuter);
  for (int threads : {1, 2}) {
    INFO(threads << " threads");
    const SelfCollisionEstimate got =
        estimate_self_collision(r.model, solids, carried, shrunk, locked, 400, 3 + 7919, threads);
    CHECK(got.false_positives == want_shrunk.false_positives);
    CHECK(got.false_negatives == want_shrunk.false_negatives);
    CHECK(alone_map(got) == alone_map(want_shrunk));
  }
  // A matrix naming a link the robot lacks is refused by name.
  SelfCollisionMatrix ghost = m;
  ghost.pairs[0].link2 = "ghost";
  CHECK_THROWS_WITH(estimate_self_collision(r.model, solids, carried, ghost, locked, 10, 1, 1),
                    Contains("\"ghost\", no link of the robot"));
  // None asked: none computed.
  request.self_collision.estimate = 0;
  SelfCollisionRun none;
  make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request, &none);
  CHECK(none.estimate.samples == 0);
}

TEST_CASE("planner setup: --tool-frame, an SRDF's pairs and end effectors, bad options",
          "[robot][self_collision]") {
  TempDir dir;
  const BakedRobot r = generated_arm(dir, 6, true);
  PlannerRequest request;
  request.self_collision.samples = 300;
  request.tool_frames = {"link3"};
  PlannerSetup s = make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request);
  CHECK(s.tool_frames == Names{"link3"});
  CHECK(s.tool_frames_from == "option");
  CHECK(s.locked_joints.empty());  // arm joints between link3 and the fingers

  request.tool_frames.clear();
  request.srdf = dir.write("arm.srdf", R"(<robot name="arm">
  <end_effector name="gripper" parent_link="flange" group="hand"/>
  <disable_collisions link1="base" link2="link4" reason="Never"/>
  <disable_collisions link1="link2" link2="left_finger" reason="User"/>
</robot>)");
  s = make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request);
  CHECK(s.tool_frames == Names{"flange"});
  CHECK(s.tool_frames_from == "srdf");
  CHECK(s.locked_joints == Names{"left_finger_joint"});
  CHECK(s.self_collision->srdf == request.srdf);
  int given = 0;
  for (const LinkPairClass& p : s.self_collision->pairs)
    if (p.kind == PairClass::kGiven) {
      ++given;
      CHECK(p.ignored);
      CHECK(p.reason == (p.link1 == "base" ? "Never" : "User"));
    }
  CHECK(given == 2);
  // --free-joint: the finger joint the rules lock stays free (its mimic twin follows it).
  request.free_joints = {"left_finger_joint"};
  s = make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request);
  CHECK(s.tool_frames == Names{"flange"});
  CHECK(s.locked_joints.empty());
  CHECK(planner_request_text(request).find("free_joints=left_finger_joint,") != std::string::npos);
  for (const auto& [name, problem] : {std::pair{"ghost", "no joint"},
                                      {"hand_joint", "fixed"},
                                      {"right_finger_joint", "mimic"},
                                      {"joint1", "not locked"}}) {
    request.free_joints = {name};
    CHECK_THROWS_WITH(make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request),
                      Contains(name) && Contains(problem) && Contains("free_joint"));
    CHECK_THROWS_WITH(check_planner_request(r.model, request), Contains(name) && Contains(problem));
  }
  request.free_joints.clear();
  CHECK(planner_request_text(request).find("free_joints") == std::string::npos);

  request.srdf.clear();
  request.tool_frames = {"ghost"};
  CHECK_THROWS_WITH(make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request),
                    Contains("ghost") && Contains("no link"));
  request.tool_frames.clear();
  request.srdf =
      dir.write("bad.srdf", "<robot><disable_collisions link1=\"base\" link2=\"nope\"/></robot>");
  CHECK_THROWS_WITH(make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request),
                    Contains("nope"));
  request.srdf = (dir.path() / "missing.srdf").string();
  CHECK_THROWS_WITH(make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request),
                    Contains("missing.srdf"));
  request.srdf.clear();
  for (auto change : {+[](SelfCollisionOptions& o) { o.samples = 0; },
                      +[](SelfCollisionOptions& o) { o.threshold = 0; },
                      +[](SelfCollisionOptions& o) { o.threshold = 1.5; },
                      +[](SelfCollisionOptions& o) { o.margin = -1; }}) {
    PlannerRequest bad = request;
    change(bad.self_collision);
    CHECK_THROWS_AS(make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, bad),
                    InputError);
  }
}

// Not in the sanitizer builds: their G1 bake is the robot bake test's, and the matrix's
// code runs there on the generated arms (support/sanitizer_build.h).
#if defined(MEDSPHERES_SHARED_MESHES) && !MEDSPHERES_TEST_SANITIZER_BUILD
TEST_CASE("the G1's matrix: no checked pair's spheres touch at its default configuration",
          "[robot][self_collision][shared]") {
  const std::string urdf =
      std::string(MEDSPHERES_SHARED_MESHES) + "/../robots/unitree_g1/g1_29dof_rev_1_0.urdf";
  if (!std::filesystem::exists(urdf)) return;  // an older ../shared without robots
  const BakedRobot r = bake(urdf, 8);
  PlannerRequest request;
  request.self_collision.samples = 300;
  const PlannerSetup s =
      make_planner_setup(r.model, r.solids, formats::SphereChoice::kOuter, request);
  // The arms' ends first (ten joints from the pelvis, the legs' six), each the hand fixed
  // to its wrist.
  CHECK(s.tool_frames == Names{"left_rubber_hand", "right_rubber_hand", "left_ankle_roll_link",
                               "right_ankle_roll_link"});
  // With 8 spheres a link the covers stick out far: the shoulders' touch the torso's in
  // every sample, so the zero pose is kept with buffers.
  CHECK(s.default_from != "zero_not_free");
  INFO("default from " << s.default_from);
  const Poses X0 = KinematicTree(r.model).link_poses(s.default_positions);
  std::size_t checked = 0;
  for (const LinkPairClass& p : s.self_collision->pairs) {
    if (p.ignored) continue;
    ++checked;
    const std::size_t a = link_index(r.model, p.link1), b = link_index(r.model, p.link2);
    INFO(p.link1 << " " << p.link2);
    CHECK(!planner_touch(r.model, *s.self_collision, X0, a, b));
  }
  CHECK(checked > 100);
}
#endif
