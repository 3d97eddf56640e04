// The planner setup's plain-data helpers: default tool frames, finger joints, the clamped zero
// pose, adjacency, the default setup and its validation (planner_setup.h).
#include "medspheres/planner_setup.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "gripper_joints.h"
#include "link_tree.h"
#include "medspheres/error.h"
#include "medspheres/robot_model.h"

namespace medspheres {

namespace {

constexpr const char* kClassNames[] = {"adjacent", "always",  "never", "sphere_only",
                                       "default",  "checked", "given"};

// The tree, and which joints are a gripper's or a hand's (gripper_joints.h): its fingers.
struct Tree : detail::LinkTree {
  std::vector<bool> gripper;
  const Joint* first;

  explicit Tree(const RobotModel& m)
      : LinkTree(m), gripper(detail::gripper_joints(m)), first(m.joints.data()) {}
  bool is_finger(const Joint& j) const { return gripper[std::size_t(&j - first)]; }
  bool moves_arm(const Joint& j) const { return j.type != JointType::kFixed && !is_finger(j); }
};

// The links below \p from (itself included) reached through joints \p follow accepts.
template <class Follow>
std::vector<std::size_t> reach(const RobotModel& m, const Tree& t, std::size_t from,
                               Follow&& follow) {
  std::vector<std::size_t> out{from};
  for (std::size_t k = 0; k < out.size(); ++k)
    for (const Joint* j : t.children[out[k]])
      if (follow(*j)) out.push_back(Tree::index(m, j->child));
  return out;
}

std::size_t finger_children(const Tree& t, std::size_t link) {
  return std::size_t(std::count_if(t.children[link].begin(), t.children[link].end(),
                                   [&t](const Joint* j) { return t.is_finger(*j); }));
}

// The link that carries the gripper of the branch that ends at link \p end (or none): the
// first link by index, below \p end through fixed and finger joints, with two or more finger
// children (a gripper's jaws), so that a prismatic joint above the jaws (a telescoping arm)
// stays a joint of the arm; else the first, through fixed joints only, with a finger child.
std::optional<std::size_t> gripper_carrier(const RobotModel& m, const Tree& t, std::size_t end) {
  const auto first_with = [&](auto&& follow, std::size_t fingers) -> std::optional<std::size_t> {
    std::optional<std::size_t> out;
    for (std::size_t r : reach(m, t, end, follow))
      if (finger_children(t, r) >= fingers && (!out || r < *out)) out = r;
    return out;
  };
  if (auto jaws = first_with([&t](const Joint& j) { return !t.moves_arm(j); }, 2)) return jaws;
  return first_with([](const Joint& j) { return j.type == JointType::kFixed; }, 1);
}

// The moving (not fixed) joints between the root and link \p l.
std::size_t moving_joints_above(const RobotModel& m, const Tree& t, std::size_t l) {
  std::size_t n = 0;
  for (const Joint* j = t.parent[l]; j != nullptr; j = t.parent[Tree::index(m, j->parent)])
    n += j->type != JointType::kFixed;
  return n;
}

// Whether \p name is \p stem, or ends with "_" and it.
bool named(const std::string& name, const std::string& stem) {
  if (name.size() < stem.size() || name.compare(name.size() - stem.size(), stem.size(), stem) != 0)
    return false;
  return name.size() == stem.size() || name[name.size() - stem.size() - 1] == '_';
}

// How telling a link's name is of a tool frame (lower is more; npos: not one): "tool0" or
// another "toolN" (ROS-Industrial's flange frames), then "tool_frame", "tcp", "grasp_frame",
// "ee_link", "end_effector_link", "end_effector", "ee", "hand"; the name itself or a suffix
// after "_", in any case.
std::size_t tool_name_rank(std::string name) {
  static const char* const kNames[] = {
      "tool_frame",        "tcp",          "grasp_frame", "ee_link",
      "end_effector_link", "end_effector", "ee",          "hand"};
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  const std::size_t digits_from = name.find_last_not_of("0123456789") + 1;  // 0 if all digits
  if (digits_from < name.size() && named(name.substr(0, digits_from), "tool")) return 0;
  for (std::size_t k = 0; k < std::size(kNames); ++k)
    if (named(name, kNames[k])) return k + 1;
  return std::string::npos;
}

// The link below the branch end \p end, through fixed joints, whose name is the most
// telling of a tool frame (tool_name_rank; then the nearest, then the first in model
// order), or none.
std::optional<std::size_t> named_tool_frame(const RobotModel& m, const Tree& t, std::size_t end) {
  std::optional<std::size_t> best;
  std::size_t best_rank = std::string::npos;
  for (std::size_t r : reach(m, t, end, [](const Joint& j) { return j.type == JointType::kFixed; }))
    if (const std::size_t k = tool_name_rank(m.links[r].name); r != end && k < best_rank) {
      best = r;
      best_rank = k;
    }
  return best;
}

[[noreturn]] void fail(const std::string& source, const std::string& problem) {
  throw InputError(source, "planner: " + problem);
}

}  // namespace

const char* pair_class_name(PairClass kind) {
  return kClassNames[static_cast<int>(kind)];
}

std::optional<PairClass> parse_pair_class(const std::string& name) {
  for (int k = 0; k <= static_cast<int>(PairClass::kGiven); ++k)
    if (name == kClassNames[k]) return static_cast<PairClass>(k);
  return std::nullopt;
}

const char* srdf_reason(PairClass kind) {
  switch (kind) {
    case PairClass::kAdjacent:
      return "Adjacent";
    case PairClass::kAlways:
      return "Always";
    case PairClass::kNever:
    case PairClass::kSphereOnly:
      return "Never";
    case PairClass::kGiven:
      return "User";
    case PairClass::kDefault:
    case PairClass::kChecked:
      break;
  }
  return "";
}

std::vector<std::string> default_tool_frames(const RobotModel& model, std::string* from) {
  const Tree t(model);
  std::vector<bool> is_tool(model.links.size(), false), by_gripper(model.links.size(), false),
      by_name(model.links.size(), false);
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    if (t.parent[l] != nullptr && !t.moves_arm(*t.parent[l])) continue;
    // A branch's end (or the root of a robot whose arm joints are none): below it, only
    // fixed and finger joints. Any arm joint reachable from the root has its parent link
    // reached through non-arm joints, so the root is an end exactly when there is none.
    const auto non_arm = [&t](const Joint& j) { return !t.moves_arm(j); };
    bool end = true;
    for (std::size_t b : reach(model, t, l, non_arm))
      for (const Joint* j : t.children[b]) end = end && !t.moves_arm(*j);
    if (!end) continue;
    // A gripper's carrier, else the tool frame fixed to the branch's end, else the end.
    const std::optional<std::size_t> carrier = gripper_carrier(model, t, l);
    const std::optional<std::size_t> frame = carrier ? carrier : named_tool_frame(model, t, l);
    const std::size_t tool = frame.value_or(l);
    is_tool[tool] = true;
    by_gripper[tool] = carrier.has_value();
    by_name[tool] = frame && !carrier;
  }
  // The grippers' carriers first (a planner takes the first as its primary end effector),
  // then the longest chains: an arm's end before a head's or a leg's.
  std::vector<std::size_t> order;
  for (std::size_t l = 0; l < model.links.size(); ++l)
    if (is_tool[l]) order.push_back(l);
  const auto depth = [&](std::size_t l) { return moving_joints_above(model, t, l); };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (by_gripper[a] != by_gripper[b]) return bool(by_gripper[a]);
    return depth(a) > depth(b);
  });
  std::vector<std::string> out;
  for (std::size_t l : order) {
    if (out.empty() && from)
      *from = by_gripper[l] ? "gripper"
              : by_name[l]  ? "frame"
                            : (t.parent[l] == nullptr ? "root" : "branch");
    out.push_back(model.links[l].name);
  }
  return out;
}

std::vector<std::string> finger_joints(const RobotModel& model,
                                       const std::vector<std::string>& tool_frames) {
  const Tree t(model);
  std::set<std::string> names;
  for (const std::string& tool : tool_frames)
    for (std::size_t l : reach(model, t, Tree::index(model, tool),
                               [&t](const Joint& j) { return !t.moves_arm(j); }))
      for (const Joint* j : t.children[l])
        if (t.is_finger(*j) && !j->mimic) names.insert(j->name);
  std::vector<std::string> out;
  std::size_t actuated = 0;
  for (const Joint& j : model.joints) {
    actuated += is_actuated(j);
    if (names.count(j.name)) out.push_back(j.name);
  }
  // A hand or a gripper alone: its fingers are all a planner has to move.
  if (out.size() == actuated) out.clear();
  return out;
}

std::map<std::string, double> clamped_zero(const RobotModel& model) {
  std::map<std::string, double> out;
  for (const Joint& j : model.joints) {
    if (!is_actuated(j)) continue;
    double q = 0.0;
    if (j.type != JointType::kContinuous && j.limits && j.limits->lower < j.limits->upper)
      q = std::clamp(q, j.limits->lower, j.limits->upper);
    out[j.name] = q;
  }
  return out;
}

std::vector<std::size_t> rigid_bodies(const RobotModel& model) {
  const detail::LinkTree t(model);
  std::vector<std::size_t> body(model.links.size());
  // Up through fixed joints to the body's top link, then the body's first link.
  std::vector<std::size_t> top(model.links.size());
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    std::size_t r = l;
    while (t.parent[r] != nullptr && t.parent[r]->type == JointType::kFixed)
      r = detail::LinkTree::index(model, t.parent[r]->parent);
    top[l] = r;
  }
  std::map<std::size_t, std::size_t> first;  // top -> first link in model order
  for (std::size_t l = 0; l < model.links.size(); ++l) first.emplace(top[l], l);
  for (std::size_t l = 0; l < model.links.size(); ++l) body[l] = first.at(top[l]);
  return body;
}

std::vector<std::pair<std::size_t, std::size_t>> adjacent_link_pairs(
    const RobotModel& model, const std::vector<bool>& has_geometry) {
  if (has_geometry.size() != model.links.size())
    throw std::invalid_argument("adjacent_link_pairs: has_geometry is not one flag per link");
  const detail::LinkTree t(model);
  const std::vector<std::size_t> body = rigid_bodies(model);
  const auto parent = [&](std::size_t l) {
    return detail::LinkTree::index(model, t.parent[l]->parent);
  };
  std::set<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    if (!has_geometry[l]) continue;
    // Up through fixed joints: a link with geometry there carries l rigidly (a rigid pair,
    // not a joint's), and the body's moving joint is that link's.
    std::size_t w = l;
    bool carried = false;
    while (!carried && t.parent[w] != nullptr && t.parent[w]->type == JointType::kFixed) {
      w = parent(w);
      carried = has_geometry[w];
    }
    if (carried || t.parent[w] == nullptr) continue;
    // Across the moving joint, up to the nearest link with geometry, or to a link without
    // it whose rigid body has some (those links stand for it).
    for (std::size_t a = parent(w);; a = parent(a)) {
      if (has_geometry[a]) {
        out.insert(std::minmax(a, l));
        break;
      }
      bool found = false;
      for (std::size_t x = 0; x < model.links.size(); ++x)
        if (body[x] == body[a] && has_geometry[x]) {
          out.insert(std::minmax(x, l));
          found = true;
        }
      if (found || t.parent[a] == nullptr) break;
    }
  }
  return {out.begin(), out.end()};
}

std::vector<std::pair<std::size_t, std::size_t>> rigid_link_pairs(
    const RobotModel& model, const std::vector<bool>& has_geometry) {
  if (has_geometry.size() != model.links.size())
    throw std::invalid_argument("rigid_link_pairs: has_geometry is not one flag per link");
  const std::vector<std::size_t> body = rigid_bodies(model);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t a = 0; a < model.links.size(); ++a)
    for (std::size_t b = a + 1; b < model.links.size(); ++b)
      if (has_geometry[a] && has_geometry[b] && body[a] == body[b]) out.emplace_back(a, b);
  return out;
}

PlannerSetup planner_setup_or_default(const RobotModel& model,
                                      const std::vector<bool>& has_spheres) {
  if (model.planner) return *model.planner;
  if (has_spheres.size() != model.links.size())
    throw std::invalid_argument("planner_setup_or_default: has_spheres is not one flag per link");
  PlannerSetup s;
  s.tool_frames = default_tool_frames(model, &s.tool_frames_from);
  s.locked_joints = finger_joints(model, s.tool_frames);
  s.default_positions = clamped_zero(model);
  s.default_from = "zero_unchecked";
  const std::vector<bool>& geometry = has_spheres;
  SelfCollisionMatrix m;
  const auto adjacent = adjacent_link_pairs(model, geometry);
  const auto rigid = rigid_link_pairs(model, geometry);
  for (std::size_t a = 0; a < model.links.size(); ++a)
    for (std::size_t b = a + 1; b < model.links.size(); ++b) {
      if (!geometry[a] || !geometry[b]) continue;
      const bool adj = std::binary_search(adjacent.begin(), adjacent.end(), std::pair{a, b}) ||
                       std::binary_search(rigid.begin(), rigid.end(), std::pair{a, b});
      m.pairs.push_back({model.links[a].name, model.links[b].name,
                         adj ? PairClass::kAdjacent : PairClass::kChecked, adj, ""});
    }
  for (std::size_t a = 0; a < model.links.size(); ++a)
    if (geometry[a]) m.buffer[model.links[a].name] = 0.0;
  s.self_collision = std::move(m);
  return s;
}

std::vector<std::string> listed_tool_frames(const RobotModel& model,
                                            const std::vector<std::string>& tool_frames,
                                            const std::vector<bool>& has_spheres) {
  if (has_spheres.size() != model.links.size())
    throw std::invalid_argument("listed_tool_frames: has_spheres is not one flag per link");
  const detail::LinkTree t(model);
  // The links on a path from the root to a tool frame or a link with spheres.
  std::vector<bool> in_tree(model.links.size(), false);
  const auto add_path = [&](std::size_t l) {
    for (;;) {
      if (in_tree[l]) return;
      in_tree[l] = true;
      if (t.parent[l] == nullptr) return;
      l = detail::LinkTree::index(model, t.parent[l]->parent);
    }
  };
  for (const std::string& f : tool_frames) add_path(detail::LinkTree::index(model, f));
  for (std::size_t l = 0; l < model.links.size(); ++l)
    if (has_spheres[l]) add_path(l);
  // Dangling actuated joints: their child links outside the tree. The lowest ones' children
  // are listed; each one's path takes in the dangling joints above it.
  std::vector<bool> dangling(model.links.size(), false);
  for (std::size_t l = 0; l < model.links.size(); ++l)
    dangling[l] = !in_tree[l] && t.parent[l] != nullptr && t.parent[l]->type != JointType::kFixed &&
                  !t.parent[l]->mimic;
  std::vector<bool> has_dangling_below(model.links.size(), false);
  for (std::size_t l = 0; l < model.links.size(); ++l) {
    if (!dangling[l]) continue;
    for (const Joint* j = t.parent[l]; j != nullptr;) {
      const std::size_t p = detail::LinkTree::index(model, j->parent);
      has_dangling_below[p] = true;
      j = t.parent[p];
    }
  }
  std::vector<std::string> out = tool_frames;
  for (std::size_t l = 0; l < model.links.size(); ++l)
    if (dangling[l] && !has_dangling_below[l]) out.push_back(model.links[l].name);
  return out;
}

std::string tool_frames_from_text(const std::string& from) {
  static const std::map<std::string, std::string> text = {
      {"option", "as given"},
      {"srdf", "the SRDF's end effectors"},
      {"gripper", "per branch, the link that carries the gripper or hand"},
      {"frame", "per branch, the tool frame fixed to the arm's end (tool0, tool_frame, tcp, ...)"},
      {"branch", "per branch, the last link an arm joint moves"},
      {"root", "the root link: the robot has no arm joint"}};
  const auto it = text.find(from);
  return it == text.end() ? from : it->second;
}

std::string default_from_text(const std::string& from) {
  static const std::map<std::string, std::string> text = {
      {"zero", "the zero pose clamped into the limits, free"},
      {"sample", "the free configuration nearest to the zero pose (the zero pose is not free)"},
      {"zero_buffered",
       "the zero pose clamped into the limits, free once self-collision buffers shrink the "
       "spheres of the links that touch there (no free configuration was found)"},
      {"zero_not_free", "the zero pose clamped into the limits, NOT free: no free one was found"},
      {"zero_unchecked", "the zero pose clamped into the limits (not checked)"}};
  const auto it = text.find(from);
  return it == text.end() ? from : it->second;
}

std::vector<std::pair<std::string, std::string>> ignored_pairs(const SelfCollisionMatrix& m) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const LinkPairClass& p : m.pairs)
    if (p.ignored) out.emplace_back(p.link1, p.link2);
  return out;
}

void validate_planner_setup(const RobotModel& model, const PlannerSetup& setup,
                            const std::string& source) {
  for (const std::string& t : setup.tool_frames)
    if (!model.find_link(t)) fail(source, "the tool frame \"" + t + "\" is no link of the robot");
  std::set<std::string> actuated;
  for (const Joint& j : model.joints)
    if (is_actuated(j)) actuated.insert(j.name);
  for (const std::string& j : setup.locked_joints)
    if (!actuated.count(j)) fail(source, "the locked joint \"" + j + "\" is no actuated joint");
  for (const auto& [j, q] : setup.default_positions) {
    if (!actuated.count(j))
      fail(source, "the default position names \"" + j + "\", no actuated joint");
    if (!std::isfinite(q)) fail(source, "the default position of \"" + j + "\" is not finite");
  }
  for (const std::string& j : actuated)
    if (!setup.default_positions.count(j))
      fail(source, "joint \"" + j + "\" has no default position");
  if (!setup.self_collision) return;
  const SelfCollisionMatrix& m = *setup.self_collision;
  std::set<std::pair<std::string, std::string>> seen;
  for (const LinkPairClass& p : m.pairs) {
    const std::string who = "the pair (\"" + p.link1 + "\", \"" + p.link2 + "\")";
    if (!model.find_link(p.link1) || !model.find_link(p.link2))
      fail(source, who + " names a link the robot does not have");
    if (p.link1 == p.link2) fail(source, who + " names one link twice");
    if (!seen.insert(std::minmax(p.link1, p.link2)).second) fail(source, who + " is listed twice");
  }
  for (const auto& [link, b] : m.buffer) {
    if (!model.find_link(link))
      fail(source, "the buffer names \"" + link + "\", no link of the robot");
    if (!std::isfinite(b)) fail(source, "the buffer of \"" + link + "\" is not finite");
  }
  if (!(m.threshold >= 0.0 && m.threshold <= 1.0))
    fail(source, "the threshold " + std::to_string(m.threshold) + " is not in [0, 1]");
  if (!std::isfinite(m.margin) || m.margin < 0.0)
    fail(source, "the margin " + std::to_string(m.margin) + " is not finite and >= 0");
}

}  // namespace medspheres
