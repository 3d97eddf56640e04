// The planner keys of a robot model's files (planner_options.h).
#include "medspheres/formats/planner_options.h"

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "medspheres/forward_kinematics.h"

namespace medspheres::formats {

namespace {

std::vector<bool> spheres_flags(const RobotModel& model, const RobotSpheres& spheres) {
  std::vector<bool> out;
  for (const Link& l : model.links) out.push_back(find_link_spheres(spheres, l.name) != nullptr);
  return out;
}

// The skipped pairs between links with spheres, keyed by the earlier link (model order).
LinkPairLists ignore_lists(const RobotModel& model, const RobotSpheres& spheres,
                           const PlannerSetup& setup) {
  std::map<std::string, std::size_t> order;
  for (std::size_t i = 0; i < model.links.size(); ++i) order[model.links[i].name] = i;
  std::map<std::size_t, std::vector<std::size_t>> by_first;
  if (setup.self_collision)
    for (const LinkPairClass& p : setup.self_collision->pairs) {
      if (!p.ignored || !find_link_spheres(spheres, p.link1) ||
          !find_link_spheres(spheres, p.link2))
        continue;
      const auto [a, b] = std::minmax(order.at(p.link1), order.at(p.link2));
      by_first[a].push_back(b);
    }
  LinkPairLists out;
  for (auto& [a, list] : by_first) {
    std::sort(list.begin(), list.end());
    std::vector<std::string> names;
    for (std::size_t b : list) names.push_back(model.links[b].name);
    out.emplace_back(model.links[a].name, std::move(names));
  }
  return out;
}

std::vector<std::pair<std::string, double>> buffers(const RobotSpheres& spheres,
                                                    const PlannerSetup& setup) {
  std::vector<std::pair<std::string, double>> out;
  for (const LinkSphereList& l : spheres) {
    double b = 0.0;
    if (setup.self_collision) {
      const auto it = setup.self_collision->buffer.find(l.link);
      if (it != setup.self_collision->buffer.end()) b = it->second;
    }
    out.emplace_back(l.link, b);
  }
  return out;
}

double largest_radius(const RobotSpheres& spheres, const std::string& link) {
  double r = 0.0;
  if (const LinkSphereList* l = find_link_spheres(spheres, link))
    for (const Sphere& s : l->spheres) r = std::max(r, s.radius);
  return r;
}

// cuRobo's loaders divide by the number of sphere pairs they check (v2
// self_collision_params.py:110, v1 cuda_robot_generator.py:925), so they refuse a robot whose
// every pair of links is skipped (ZeroDivisionError). Such a robot's files check one pair
// that cannot touch instead: its first link's buffer is minus the pair's two largest radii
// and the other link's buffer, less 1 cm, so each of its sphere pairs' thresholds (r1 + r2 +
// buffer1 + buffer2, whatever collision_sphere_buffer adds) is below -1 cm. The first link's
// other pairs stay skipped, so its buffer changes nothing else.
void check_one_untouchable_pair(LinkPairLists& ignore,
                                std::vector<std::pair<std::string, double>>& buffer,
                                const RobotSpheres& spheres) {
  std::size_t skipped = 0;
  for (const auto& entry : ignore) skipped += entry.second.size();
  const std::size_t links = buffer.size();
  if (links < 2 || skipped < links * (links - 1) / 2 || ignore.empty()) return;
  const std::string a = ignore.front().first;
  const std::string b = ignore.front().second.front();
  ignore.front().second.erase(ignore.front().second.begin());
  if (ignore.front().second.empty()) ignore.erase(ignore.begin());
  double other = 0.0;
  for (const auto& [link, value] : buffer)
    if (link == b) other = value;
  for (auto& [link, value] : buffer)
    if (link == a)
      value =
          -(largest_radius(spheres, a) + largest_radius(spheres, b) + std::max(0.0, other)) - 0.01;
}

// A robot whose spheres all sit on one link checks no sphere pair, which cuRobo v2 refuses
// (PlaceholderFrame): its files add a frame at the base with a disabled sphere, named apart
// from every link of the model.
PlaceholderFrame placeholder_frame(const RobotModel& model, const RobotSpheres& spheres,
                                   const std::vector<std::pair<std::string, double>>& buffer) {
  if (spheres.size() != 1) return {};
  std::set<std::string> names;
  for (const Link& l : model.links) names.insert(l.name);
  PlaceholderFrame frame;
  frame.name = "medspheres_placeholder";
  while (names.count(frame.name)) frame.name += "_";
  frame.parent = model.root_link;
  double largest = largest_radius(spheres, spheres.front().link);
  for (const auto& entry : buffer) largest += std::max(0.0, entry.second);
  frame.radius = -(1.0 + largest);
  return frame;
}

// The keys the cuRobo file and the XRDF share: tool frames, skipped pairs and buffers.
template <class Options>
void fill_self_collision_keys(const RobotModel& model, const RobotSpheres& spheres,
                              const PlannerSetup& setup, Options& o) {
  o.tool_frames = listed_tool_frames(model, setup.tool_frames, spheres_flags(model, spheres));
  o.self_collision_ignore = ignore_lists(model, spheres, setup);
  o.self_collision_buffer = buffers(spheres, setup);
  check_one_untouchable_pair(o.self_collision_ignore, o.self_collision_buffer, spheres);
}

}  // namespace

PlannerSetup planner_setup_for(const RobotModel& model, const RobotSpheres& spheres) {
  return planner_setup_or_default(model, spheres_flags(model, spheres));
}

CuroboOptions curobo_options(const RobotModel& model, const RobotSpheres& spheres,
                             CuroboLayout layout, const std::string& urdf_path) {
  const PlannerSetup setup = planner_setup_for(model, spheres);
  CuroboOptions o;
  o.layout = layout;
  o.base_link = model.root_link;
  o.urdf_path = urdf_path;
  fill_self_collision_keys(model, spheres, setup, o);
  if (layout == CuroboLayout::kV2)
    o.placeholder = placeholder_frame(model, spheres, o.self_collision_buffer);
  const KinematicTree tree(model);
  for (const std::string& j : tree.joint_names()) {
    o.joint_names.push_back(j);
    o.default_positions.push_back(setup.default_positions.at(j));
  }
  for (const std::string& j : setup.locked_joints)
    o.lock_joints.emplace_back(j, setup.default_positions.at(j));
  return o;
}

std::size_t curobo_sphere_pairs(const RobotModel& model, const RobotSpheres& spheres) {
  CuroboOptions keys;
  fill_self_collision_keys(model, spheres, planner_setup_for(model, spheres), keys);
  std::set<std::pair<std::string, std::string>> skipped;
  for (const auto& [link, others] : keys.self_collision_ignore)
    for (const std::string& other : others) skipped.insert(std::minmax(link, other));
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < spheres.size(); ++i)
    for (std::size_t j = i + 1; j < spheres.size(); ++j)
      if (!skipped.count(std::minmax(spheres[i].link, spheres[j].link)))
        pairs += spheres[i].spheres.size() * spheres[j].spheres.size();
  return pairs;
}

XrdfOptions xrdf_options(const RobotModel& model, const RobotSpheres& spheres) {
  const PlannerSetup setup = planner_setup_for(model, spheres);
  XrdfOptions o;
  o.base_frame = model.root_link;
  const std::set<std::string> locked(setup.locked_joints.begin(), setup.locked_joints.end());
  const KinematicTree tree(model);
  for (const std::string& j : tree.joint_names()) {
    if (!locked.count(j)) o.joint_names.push_back(j);
    o.default_positions.emplace_back(j, setup.default_positions.at(j));
  }
  fill_self_collision_keys(model, spheres, setup, o);
  o.placeholder = placeholder_frame(model, spheres, o.self_collision_buffer);
  return o;
}

std::vector<DisabledCollision> srdf_disabled_pairs(const RobotModel& model,
                                                   const RobotSpheres& spheres) {
  const PlannerSetup setup = planner_setup_for(model, spheres);
  std::vector<DisabledCollision> out;
  if (!setup.self_collision) return out;
  for (const LinkPairClass& p : setup.self_collision->pairs)
    if (p.ignored)
      out.push_back(
          {p.link1, p.link2, p.kind == PairClass::kGiven ? p.reason : srdf_reason(p.kind)});
  return out;
}

}  // namespace medspheres::formats
