#include "medspheres/robot_model.h"

#include <cmath>
#include <set>
#include <unordered_map>
#include <utility>

#include "medspheres/error.h"

namespace medspheres {

const Link* RobotModel::find_link(const std::string& link_name) const {
  for (const Link& l : links)
    if (l.name == link_name) return &l;
  return nullptr;
}

const Joint* RobotModel::find_joint(const std::string& joint_name) const {
  for (const Joint& j : joints)
    if (j.name == joint_name) return &j;
  return nullptr;
}

const char* joint_type_name(JointType type) {
  switch (type) {
    case JointType::kFixed:
      return "fixed";
    case JointType::kRevolute:
      return "revolute";
    case JointType::kContinuous:
      return "continuous";
    case JointType::kPrismatic:
      return "prismatic";
  }
  return "unknown";
}

namespace {

std::string quoted(const std::string& what, const std::string& name) {
  return what + " \"" + name + "\"";
}

bool finite(const Eigen::Isometry3d& x) {
  return x.matrix().allFinite();
}

// Names non-empty and unique, spheres valid.
void check_links(const RobotModel& m, const std::string& source) {
  if (m.links.empty()) throw InputError(source, "the robot has no links");
  std::set<std::string> seen;
  for (const Link& l : m.links) {
    if (l.name.empty()) throw InputError(source, "a link has an empty name");
    if (!seen.insert(l.name).second)
      throw InputError(source, quoted("link", l.name) + " is defined twice");
    for (const auto& [set, which] : {std::pair{&l.spheres.inner, " inner set: "},
                                     std::pair{&l.spheres.outer, " outer set: "}}) {
      try {
        validate_sphere_set(*set, source);
      } catch (const InputError& e) {
        throw InputError(source, quoted("link", l.name) + which + e.problem());
      }
    }
  }
}

void check_joint_numbers(const Joint& j, const std::string& source) {
  const std::string who = quoted("joint", j.name);
  if (!finite(j.origin)) throw InputError(source, who + ": the origin is not finite");
  if (!j.axis.allFinite()) throw InputError(source, who + ": the axis is not finite");
  if (j.type != JointType::kFixed && j.axis.norm() == 0.0)
    throw InputError(source, who + ": the axis is zero");
  if (j.limits) {
    const JointLimits& l = *j.limits;
    if (!std::isfinite(l.lower) || !std::isfinite(l.upper) || !std::isfinite(l.velocity) ||
        !std::isfinite(l.effort))
      throw InputError(source, who + ": a limit is not finite");
    if (l.lower > l.upper)
      throw InputError(source, who + ": the lower limit " + std::to_string(l.lower) +
                                   " exceeds the upper limit " + std::to_string(l.upper));
  }
  if (j.mimic && (!std::isfinite(j.mimic->multiplier) || !std::isfinite(j.mimic->offset)))
    throw InputError(source, who + ": the mimic multiplier or offset is not finite");
}

// Every joint joins two existing, different links; no link has two parents; one root,
// reaching every link.
void check_tree(const RobotModel& m, const std::string& source) {
  std::unordered_map<std::string, const Joint*> parent_joint;
  std::set<std::string> joint_names;
  std::unordered_map<std::string, std::vector<std::string>> children;
  for (const Joint& j : m.joints) {
    const std::string who = quoted("joint", j.name);
    if (j.name.empty()) throw InputError(source, "a joint has an empty name");
    if (!joint_names.insert(j.name).second) throw InputError(source, who + " is defined twice");
    for (const std::string* end : {&j.parent, &j.child})
      if (!m.find_link(*end))
        throw InputError(source, who + " names the link \"" + *end + "\", which does not exist");
    if (j.parent == j.child)
      throw InputError(source, who + " joins the link \"" + j.child + "\" to itself");
    const auto [it, inserted] = parent_joint.emplace(j.child, &j);
    if (!inserted)
      throw InputError(source, quoted("link", j.child) + " has two parents: joints \"" +
                                   it->second->name + "\" and \"" + j.name + "\"");
    children[j.parent].push_back(j.child);
    check_joint_numbers(j, source);
  }
  std::vector<std::string> roots;
  for (const Link& l : m.links)
    if (!parent_joint.count(l.name)) roots.push_back(l.name);
  if (roots.empty())
    throw InputError(source, "every link has a parent: the joints form a cycle (through link \"" +
                                 m.links.front().name + "\")");
  if (roots.size() > 1)
    throw InputError(source, "the links \"" + roots[0] + "\" and \"" + roots[1] +
                                 "\" both have no parent: the robot is not one tree");
  if (!m.root_link.empty() && m.root_link != roots[0])
    throw InputError(source, "the root link is \"" + m.root_link + "\", but the link with no " +
                                 "parent is \"" + roots[0] + "\"");
  std::set<std::string> reached{roots[0]};
  std::vector<std::string> stack{roots[0]};
  while (!stack.empty()) {
    const std::string l = stack.back();
    stack.pop_back();
    for (const std::string& c : children[l])
      if (reached.insert(c).second) stack.push_back(c);
  }
  for (const Link& l : m.links)
    if (!reached.count(l.name))
      throw InputError(source, quoted("link", l.name) + " is not reached from the root link \"" +
                                   roots[0] + "\": its joints form a cycle");
}

// A mimic joint moves and follows an existing moving joint; the chain of sources ends.
void check_mimics(const RobotModel& m, const std::string& source) {
  for (const Joint& j : m.joints) {
    if (!j.mimic) continue;
    const std::string who = quoted("joint", j.name);
    if (j.type == JointType::kFixed) throw InputError(source, who + " is fixed but mimics a joint");
    const Joint* at = &j;
    for (std::size_t steps = 0; at->mimic; ++steps) {
      const Joint* next = m.find_joint(at->mimic->joint);
      if (!next)
        throw InputError(source, quoted("joint", at->name) + " mimics the joint \"" +
                                     at->mimic->joint + "\", which does not exist");
      if (next->type == JointType::kFixed)
        throw InputError(
            source, quoted("joint", at->name) + " mimics the fixed joint \"" + next->name + "\"");
      if (next == &j || steps > m.joints.size())
        throw InputError(source, who + ": its chain of mimic sources forms a loop");
      at = next;
    }
  }
}

}  // namespace

void validate_robot_model(const RobotModel& model, const std::string& source) {
  check_links(model, source);
  check_tree(model, source);
  check_mimics(model, source);
  if (model.planner) validate_planner_setup(model, *model.planner, source);
}

}  // namespace medspheres
