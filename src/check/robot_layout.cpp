#include "robot_layout.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "medspheres/error.h"
#include "medspheres/forward_kinematics.h"
#include "medspheres/min_enclosing_ball.h"
#include "medspheres/self_pairs.h"
#include "medspheres/sphere_set.h"

namespace medspheres::check::detail {
namespace {

constexpr const char* kSource = "robot checker";

void row_major(const Eigen::Matrix3d& m, double* out) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = m(r, c);
}

// The fine model must move as the planner's: the same links, the same joints (origins to
// 1e-12: a robot file's rotation reads back as its quaternion's matrix, robot_file.h).
void check_same_robot(const RobotModel& planner, const RobotModel& fine) {
  for (const Link& l : planner.links)
    if (fine.find_link(l.name) == nullptr)
      throw InputError(kSource, "the fine sets have no link \"" + l.name + "\"");
  if (fine.links.size() != planner.links.size() || fine.joints.size() != planner.joints.size())
    throw InputError(kSource, "the fine sets' robot has other links or joints than the planner's");
  for (const Joint& j : planner.joints) {
    const Joint* f = fine.find_joint(j.name);
    if (f == nullptr || f->type != j.type || f->parent != j.parent || f->child != j.child ||
        (f->origin.matrix() - j.origin.matrix()).cwiseAbs().maxCoeff() > 1e-12 ||
        (f->axis - j.axis).cwiseAbs().maxCoeff() > 1e-12)
      throw InputError(kSource,
                       "joint \"" + j.name + "\" of the fine sets differs from the planner's");
  }
}

// The step of a moving joint whose joint frame J sits at X_PJ in the moving parent frame.
FrameStep moving_step(const KinematicTree::Step& s, int frame, int parent,
                      const Eigen::Isometry3d& X_PJ) {
  FrameStep f;
  f.frame = frame;
  f.parent = parent;
  f.prismatic = s.type == JointType::kPrismatic;
  f.source = static_cast<int>(s.source);
  f.multiplier = s.multiplier;
  f.offset = s.offset;
  const Eigen::Matrix3d M = X_PJ.linear();
  const Eigen::Vector3d a = s.axis;
  for (int k = 0; k < 3; ++k) f.u[k] = X_PJ.translation()[k];
  if (f.prismatic) {
    row_major(M, f.P);
    const Eigen::Vector3d v = M * a;
    for (int k = 0; k < 3; ++k) f.v[k] = v[k];
    return f;
  }
  // Rodrigues: R(q) = a a^T + cos q (I - a a^T) + sin q [a]x.
  Eigen::Matrix3d cross;
  cross << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  const Eigen::Matrix3d aa = a * a.transpose();
  row_major(M * aa, f.P);
  row_major(M * (Eigen::Matrix3d::Identity() - aa), f.C);
  row_major(M * cross, f.S);
  for (int e = 0; e < 9; ++e) {
    f.Pf[e] = static_cast<float>(f.P[e]);
    f.Cf[e] = static_cast<float>(f.C[e]);
    f.Sf[e] = static_cast<float>(f.S[e]);
  }
  for (int k = 0; k < 3; ++k) f.uf[k] = static_cast<float>(f.u[k]);
  return f;
}

// Every two links with geometry but the links of a joint and the disabled pairs.
void add_self_pairs(const RobotModel& model, const std::vector<std::string>& names,
                    const std::vector<std::pair<std::string, std::string>>& disabled,
                    RobotLayout& out) {
  const std::set<LinkPair> skip = skipped_self_pairs(model, disabled);
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t k = i + 1; k < names.size(); ++k)
      if (skip.count(ordered_pair(names[i], names[k])) == 0) {
        out.pair_a.push_back(static_cast<std::uint32_t>(i));
        out.pair_b.push_back(static_cast<std::uint32_t>(k));
      }
}

// The inner set that bounds a link from inside: none for a filled solid's balls (they may
// sit in a thin shell's cavity, outside the material) when a covering set stands for the
// link in the spheres mode.
const std::vector<Sphere>* held_inner(const LinkSpheres& s) {
  static const std::vector<Sphere> none;
  return s.inner_filled && !s.outer.empty() ? &none : &s.inner.spheres;
}

// The inner points of make_layout, checked against the planner's links.
void check_inner_points(const RobotModel& planner,
                        const std::map<std::string, std::vector<Sphere>>& points) {
  for (const auto& [name, spheres] : points) {
    const Link* l = planner.find_link(name);
    if (l == nullptr)
      throw InputError(kSource, "inner points name an unknown link \"" + name + "\"");
    if (l->spheres.outer.empty() && !spheres.empty())
      throw InputError(kSource, "inner points for link \"" + name +
                                    "\", which has no covering set (its inner set is the "
                                    "spheres mode's)");
    SphereSet set;
    set.spheres = spheres;
    validate_sphere_set(set, std::string(kSource) + ": the inner points of link \"" + name + "\"",
                        /*allow_points=*/true);
  }
}

// A link's sets in its frame (X_FL places the link in the frame), level by level; `extra`
// (may be null) joins the planner's inner set.
void add_link(const Link& planner, const Link* fine, int frame, const Eigen::Isometry3d& X_FL,
              const std::vector<Sphere>* extra, RobotLayout& out) {
  std::vector<Sphere> inner = *held_inner(planner.spheres);
  if (extra) inner.insert(inner.end(), extra->begin(), extra->end());
  const std::vector<Sphere>* sets[kLevels] = {&planner.spheres.outer.spheres, &inner,
                                              fine ? &fine->spheres.outer.spheres : nullptr,
                                              fine ? held_inner(fine->spheres) : nullptr};
  LinkLayout l;
  l.frame = frame;
  l.spheres = planner.spheres.outer.empty() ? kInner : kOuter;
  std::vector<Sphere> all;
  for (int k = 0; k < kLevels; ++k) {
    l.begin[k] = static_cast<std::uint32_t>(out.x.size());
    if (sets[k] == nullptr) continue;
    for (const Sphere& s : *sets[k]) {
      const Eigen::Vector3d c = X_FL * s.center;
      out.x.push_back(c.x());
      out.y.push_back(c.y());
      out.z.push_back(c.z());
      out.r.push_back(s.radius);
      out.max_radius = std::max(out.max_radius, s.radius);
      out.extent = std::max(out.extent, c.cwiseAbs().maxCoeff() + s.radius);
      all.push_back({c, s.radius});
    }
    l.count[k] = static_cast<std::uint32_t>(sets[k]->size());
  }
  const Sphere b = min_enclosing_ball(all);
  for (int k = 0; k < 3; ++k) l.bound[k] = b.center[k];
  l.bound[3] = b.radius;
  out.links.push_back(l);
  out.link_names.push_back(planner.name);
}

}  // namespace

RobotLayout make_layout(const RobotModel& planner, const RobotModel* fine,
                        const Eigen::Isometry3d& X_WB,
                        const std::vector<std::pair<std::string, std::string>>& disabled,
                        const std::map<std::string, std::vector<Sphere>>& inner_points) {
  const KinematicTree tree(planner, kSource);
  if (fine != nullptr) check_same_robot(planner, *fine);
  check_inner_points(planner, inner_points);
  RobotLayout out;
  out.dof = tree.num_positions();
  out.joint_names = tree.joint_names();
  out.fine = fine != nullptr;
  const std::size_t n = tree.link_names().size();
  std::vector<int> frame(n, 0);
  std::vector<Eigen::Isometry3d> X_FL(n, Eigen::Isometry3d::Identity());
  X_FL[tree.root()] = X_WB;  // frame 0 is W itself
  for (const KinematicTree::Step& s : tree.steps()) {
    const Eigen::Isometry3d X_PJ = X_FL[s.parent] * s.origin;
    if (s.type == JointType::kFixed) {
      frame[s.child] = frame[s.parent];
      X_FL[s.child] = X_PJ;
      continue;
    }
    frame[s.child] = out.frames++;
    out.steps.push_back(moving_step(s, frame[s.child], frame[s.parent], X_PJ));
  }
  std::vector<std::string> names;
  for (std::size_t i = 0; i < n; ++i) {
    const Link& l = planner.links[i];
    const Link* f = fine ? fine->find_link(l.name) : nullptr;
    const bool any = !l.spheres.inner.empty() || !l.spheres.outer.empty() ||
                     (f && (!f->spheres.inner.empty() || !f->spheres.outer.empty()));
    if (!any) continue;
    const auto extra = inner_points.find(l.name);
    add_link(l, f, frame[i], X_FL[i], extra != inner_points.end() ? &extra->second : nullptr, out);
    names.push_back(l.name);
  }
  add_self_pairs(planner, names, disabled, out);
  return out;
}

}  // namespace medspheres::check::detail
