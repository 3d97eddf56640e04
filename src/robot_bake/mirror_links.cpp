// A robot's left-right mirror image (mirror_links.h).
#include "medspheres/robot_bake/mirror_links.h"

#include <cmath>
#include <map>
#include <utility>

namespace medspheres {

namespace {

// \p name with every a and b exchanged; nullopt when it holds neither.
std::optional<std::string> exchange(const std::string& name, const std::string& a,
                                    const std::string& b) {
  std::string out;
  bool any = false;
  for (std::size_t i = 0; i < name.size();) {
    if (name.compare(i, a.size(), a) == 0) {
      out += b, i += a.size(), any = true;
    } else if (name.compare(i, b.size(), b) == 0) {
      out += a, i += b.size(), any = true;
    } else {
      out += name[i++];
    }
  }
  return any ? std::optional<std::string>(out) : std::nullopt;
}

// The short forms: "l_"/"r_" at the start, "_l"/"_r" at the end, "_l_"/"_r_" within.
std::optional<std::string> exchange_short(const std::string& name, char l, char r) {
  std::string out = name;
  bool any = false;
  const auto flip = [&](std::size_t i) {
    if (out[i] == l || out[i] == r) out[i] = out[i] == l ? r : l, any = true;
  };
  const std::size_t n = out.size();
  if (n >= 3 && out[1] == '_') flip(0);
  if (n >= 3 && out[n - 2] == '_') flip(n - 1);
  for (std::size_t i = 1; i + 2 < n; ++i)
    if (out[i - 1] == '_' && out[i + 1] == '_') flip(i);
  return any ? std::optional<std::string>(out) : std::nullopt;
}

// Within kTolerance: a URDF exported from CAD is symmetric to a few micrometres (the G1's
// shoulders: 4 um), and the image only makes the matrix check more pairs.
constexpr double kTolerance = 1e-3;  // metres (offsets), radians or metres (ranges)

bool same(double x, double y) {
  return std::abs(x - y) <= kTolerance;
}

// Whether joint \p k's image \p m has the same type, offset length and range of motion.
bool joint_image(const Joint& k, const Joint& m) {
  if (k.type != m.type || k.limits.has_value() != m.limits.has_value()) return false;
  if (!same(k.origin.translation().norm(), m.origin.translation().norm())) return false;
  return !k.limits || same(k.limits->upper - k.limits->lower, m.limits->upper - m.limits->lower);
}

}  // namespace

std::optional<std::string> swap_side(const std::string& name) {
  for (const auto& [a, b] :
       {std::pair<const char*, const char*>{"left", "right"}, {"Left", "Right"}, {"LEFT", "RIGHT"}})
    if (auto out = exchange(name, a, b)) return out;
  if (auto out = exchange_short(name, 'l', 'r')) return out;
  return exchange_short(name, 'L', 'R');
}

std::vector<std::size_t> mirror_links(const RobotModel& model) {
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < model.links.size(); ++i) index[model.links[i].name] = i;
  std::vector<std::size_t> image(model.links.size());
  bool sided = false;
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    const std::optional<std::string> other = swap_side(model.links[i].name);
    const auto it = other ? index.find(*other) : index.end();
    if (other && it == index.end()) return {};
    image[i] = other ? it->second : i;
    sided = sided || other.has_value();
  }
  if (!sided) return {};
  std::map<std::string, const Joint*> by_child;
  for (const Joint& j : model.joints) by_child[j.child] = &j;
  for (const Joint& j : model.joints) {
    const auto it = by_child.find(model.links[image[index.at(j.child)]].name);
    if (it == by_child.end() || !joint_image(j, *it->second) ||
        it->second->parent != model.links[image[index.at(j.parent)]].name)
      return {};
  }
  return image;
}

}  // namespace medspheres
