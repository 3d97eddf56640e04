// What keeps cuRobo's URDF parser from loading a robot (curobo_urdf_check.h).
#include "medspheres/formats/curobo_urdf_check.h"

#include <algorithm>
#include <string>

#include "number_text.h"

namespace medspheres::formats {

namespace {

// The limits of \p j that cuRobo v2 takes as the empty range [-x, x] (x not positive).
std::string empty_ranges(const Joint& j) {
  std::string out;
  if (!(j.limits->velocity > 0.0)) out = "velocity " + exact_number_text(j.limits->velocity);
  if (!(j.limits->effort > 0.0))
    out += (out.empty() ? "effort " : " and effort ") + exact_number_text(j.limits->effort);
  return out;
}

// The limits cuRobo v1's parser reads for \p j: a continuous joint's range is [-6.28, 6.28].
JointLimits v1_limits(const Joint& j) {
  JointLimits l = *j.limits;
  if (j.type == JointType::kContinuous) {
    l.lower = -6.28;
    l.upper = 6.28;
  }
  return l;
}

// What cuRobo v1's parser refuses in mimic joint \p j of \p source (its get_link_parameters):
// the source's lower or upper limit, or its velocity, mapped by the multiplier (and the
// offset) beyond the mimic's own; empty when none. v2 widens the mimic's limits instead.
std::string v1_mimic_problem(const Joint& j, const Joint& source) {
  const JointLimits own = v1_limits(j), from = v1_limits(source);
  const double m = j.mimic->multiplier, o = j.mimic->offset;
  std::string out;
  auto add = [&](const std::string& what) { out += (out.empty() ? "" : ", ") + what; };
  if (from.lower * m + o < own.lower)
    add("lower " + exact_number_text(from.lower * m + o) + " < " + exact_number_text(own.lower));
  if (from.upper * m + o > own.upper)
    add("upper " + exact_number_text(from.upper * m + o) + " > " + exact_number_text(own.upper));
  if (from.velocity * m > own.velocity)
    add("velocity " + exact_number_text(from.velocity * m) + " > " +
        exact_number_text(own.velocity));
  return out;
}

// The sentence for mimic joint \p j, or "" (no problem, or limits missing on either side).
std::string mimic_problem(const RobotModel& model, const Joint& j) {
  const Joint* source = model.find_joint(j.mimic->joint);
  if (!j.limits || !source || !source->limits || source->type == JointType::kFixed) return "";
  const std::string beyond = v1_mimic_problem(j, *source);
  if (beyond.empty()) return "";
  return "mimic joint '" + j.name + "' follows '" + source->name + "' beyond its own <limit> (" +
         beyond +
         "); cuRobo v1's URDF parser refuses the robot whatever the configuration (v2 widens "
         "the limit and loads it); widen the <limit> of '" +
         j.name + "'";
}

}  // namespace

bool writes_xrdf(const RobotModel& model) {
  return std::any_of(model.joints.begin(), model.joints.end(), is_actuated);
}

std::vector<std::string> curobo_urdf_problems(const RobotModel& model) {
  std::vector<std::string> out;
  if (!writes_xrdf(model))
    out.push_back(
        "the robot has no actuated joint, so `medspheres robot` writes no XRDF: cuRobo's "
        "XRDF loaders need a joint in its cspace (v1 and v2 take the largest of its "
        "acceleration limits); the cuRobo YAML carries the spheres");
  for (const Joint& j : model.joints) {
    if (j.type != JointType::kFixed && j.mimic) {
      const std::string problem = mimic_problem(model, j);
      if (!problem.empty()) out.push_back(problem);
    }
    if (!is_actuated(j)) continue;
    if (!j.limits) {
      if (j.type == JointType::kContinuous)
        out.push_back("continuous joint '" + j.name +
                      "' has no <limit>; cuRobo's URDF parser needs one (effort and velocity) "
                      "to load this robot with any configuration");
      continue;
    }
    const std::string empty = empty_ranges(j);
    if (!empty.empty())
      out.push_back(
          "joint '" + j.name + "' has " + empty +
          " in its <limit>; cuRobo v2's loader takes each as the range [-x, x] and refuses "
          "an empty one, whatever the configuration (v1 loads it); give the joint its "
          "real limits");
  }
  return out;
}

}  // namespace medspheres::formats
