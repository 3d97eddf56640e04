// A baked robot's planner setup (robot_planner_setup.h).
#include "medspheres/robot_bake/robot_planner_setup.h"

#include <algorithm>
#include <chrono>

#include "medspheres/error.h"
#include "medspheres/formats/srdf_disabled_collisions.h"
#include "medspheres/io.h"
#include "medspheres/number_text.h"

namespace medspheres {

namespace {

// The tool frames and how they were chosen.
std::vector<std::string> tool_frames(const RobotModel& model, const PlannerRequest& r,
                                     const std::string& srdf_text, std::string& from) {
  for (const std::string& t : r.tool_frames)
    if (!model.find_link(t))
      throw InputError::option(ErrorKind::kOutOfRange, "tool_frame", t,
                               "\"" + t + "\" is no link of the robot \"" + model.name + "\"");
  if (!r.tool_frames.empty()) {
    from = "option";
    return r.tool_frames;
  }
  if (!srdf_text.empty()) {
    std::vector<std::string> ends = formats::parse_srdf_end_effector_links(srdf_text, r.srdf);
    for (const std::string& t : ends)
      if (!model.find_link(t))
        throw InputError::option(
            ErrorKind::kOutOfRange, "srdf", r.srdf,
            "its end effector's parent_link \"" + t + "\" is no link of the robot");
    if (!ends.empty()) {
      from = "srdf";
      return ends;
    }
  }
  return default_tool_frames(model, &from);
}

// Each free joint is an actuated joint of the robot (not fixed, not a mimic joint) that the
// rules lock: one of \p fingers, the finger joints below the tool frames.
void check_free_joints(const RobotModel& model, const std::vector<std::string>& fingers,
                       const PlannerRequest& r) {
  for (const std::string& name : r.free_joints) {
    const Joint* j = model.find_joint(name);
    std::string problem;
    if (!j)
      problem = "is no joint of the robot \"" + model.name + "\"";
    else if (j->type == JointType::kFixed)
      problem = "is a fixed joint";
    else if (j->mimic)
      problem = "follows \"" + j->mimic->joint + "\" (a mimic joint): free that joint instead";
    else if (std::find(fingers.begin(), fingers.end(), name) == fingers.end())
      problem =
          "is not locked (only the finger joints below the tool frames are), so it is "
          "free already";
    if (!problem.empty())
      throw InputError::option(ErrorKind::kOutOfRange, "free_joint", name,
                               "\"" + name + "\" " + problem);
  }
}

// The finger joints \p fingers that the request does not free.
std::vector<std::string> locked_joints(const std::vector<std::string>& fingers,
                                       const PlannerRequest& r) {
  std::vector<std::string> out;
  for (const std::string& j : fingers)
    if (std::find(r.free_joints.begin(), r.free_joints.end(), j) == r.free_joints.end())
      out.push_back(j);
  return out;
}

}  // namespace

// The SRDF's text ("" without one), its unreadable file named by the option.
std::string srdf_text_of(const PlannerRequest& r) {
  if (r.srdf.empty()) return "";
  try {
    return read_text_file(r.srdf);
  } catch (const InputError& e) {
    throw e.with_field("srdf");
  }
}

std::string planner_request_text(const PlannerRequest& r) {
  const auto names = [](const std::vector<std::string>& list) {
    std::string out;
    for (const std::string& n : list) out += n + ",";
    return out;
  };
  std::string t = "planner tool_frames=" + names(r.tool_frames) + "\nsrdf=" + r.srdf +
                  "\nsample=" + (r.sample ? "1" : "0") +
                  "\nsamples=" + std::to_string(r.self_collision.samples) +
                  "\nseed=" + std::to_string(r.self_collision.seed) +
                  "\nthreshold=" + exact_number_text(r.self_collision.threshold) +
                  "\nmargin=" + exact_number_text(r.self_collision.margin) +
                  "\nsearch=" + (r.self_collision.search ? "1" : "0") + "\n";
  // Only when given, so that the keys of earlier requests stay.
  if (!r.free_joints.empty()) t += "free_joints=" + names(r.free_joints) + "\n";
  return t;
}

void check_planner_request(const RobotModel& model, const PlannerRequest& r) {
  validate(r.self_collision);
  const std::string srdf_text = srdf_text_of(r);
  std::string from;
  check_free_joints(model, finger_joints(model, tool_frames(model, r, srdf_text, from)), r);
  if (!srdf_text.empty())
    check_disabled_pairs(model, formats::parse_srdf_disabled_collisions(srdf_text, r.srdf));
}

// The run's estimate (SelfCollisionOptions::estimate configurations), unless none is asked
// for or the matrix checks no pair (nothing a planner reports).
void add_estimate(const RobotModel& model, const LinkSolids& solids,
                  const formats::RobotSpheres& spheres, const std::map<std::string, double>& locked,
                  const SelfCollisionOptions& o, SelfCollisionRun& run) {
  const auto& pairs = run.matrix.pairs;
  if (o.estimate == 0 ||
      std::none_of(pairs.begin(), pairs.end(), [](const LinkPairClass& p) { return !p.ignored; }))
    return;
  const auto t0 = std::chrono::steady_clock::now();
  run.estimate = estimate_self_collision(model, solids, spheres, run.matrix, locked, o.estimate,
                                         o.seed + 7919, o.threads);
  run.estimate_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

PlannerSetup make_planner_setup(const RobotModel& model, const std::vector<LinkSolid>& solids,
                                formats::SphereChoice carried, const PlannerRequest& r,
                                SelfCollisionRun* run_out) {
  validate(r.self_collision);
  const std::string srdf_text = srdf_text_of(r);
  PlannerSetup s;
  s.tool_frames = tool_frames(model, r, srdf_text, s.tool_frames_from);
  const std::vector<std::string> fingers = finger_joints(model, s.tool_frames);
  check_free_joints(model, fingers, r);
  s.locked_joints = locked_joints(fingers, r);
  const std::map<std::string, double> zero = clamped_zero(model);
  std::map<std::string, double> locked;
  for (const std::string& j : s.locked_joints) locked[j] = zero.at(j);
  const formats::RobotSpheres spheres = formats::robot_spheres(model, carried);
  if (!r.sample) {
    std::vector<bool> has;
    for (const Link& l : model.links) has.push_back(formats::find_link_spheres(spheres, l.name));
    RobotModel bare = model;
    bare.planner.reset();
    const PlannerSetup d = planner_setup_or_default(bare, has);
    s.default_positions = zero;
    s.default_from = "zero_unchecked";
    s.self_collision = d.self_collision;
    return s;
  }
  const std::vector<formats::DisabledCollision> given =
      srdf_text.empty() ? std::vector<formats::DisabledCollision>{}
                        : formats::parse_srdf_disabled_collisions(srdf_text, r.srdf);
  const LinkSolids link_solids(model, solids);
  SelfCollisionRun run =
      compute_self_collision(model, link_solids, spheres, locked, given, r.self_collision);
  if (!r.srdf.empty()) run.matrix.srdf = r.srdf;
  s.default_positions = run.default_positions;
  s.default_from = run.default_from;
  s.self_collision = run.matrix;
  if (!run_out) return s;
  add_estimate(model, link_solids, spheres, locked, r.self_collision, run);
  *run_out = std::move(run);
  return s;
}

}  // namespace medspheres
