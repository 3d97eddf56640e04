#include "link_reach.h"

#include <cmath>
#include <limits>

#include "scene_element.h"

namespace medspheres::check::detail {

std::vector<LinkReach> link_reach(const RobotLayout& layout) {
  std::vector<const FrameStep*> step(static_cast<std::size_t>(layout.frames), nullptr);
  for (const FrameStep& s : layout.steps) step[static_cast<std::size_t>(s.frame)] = &s;
  std::vector<LinkReach> out;
  for (const LinkLayout& l : layout.links) {
    LinkReach r{{l.bound[0], l.bound[1], l.bound[2]}, l.bound[3]};
    for (int f = l.frame; f != 0;) {
      const FrameStep& s = *step[static_cast<std::size_t>(f)];
      if (s.prismatic) {
        r.radius = std::numeric_limits<double>::infinity();
        break;
      }
      r = {step_matrix(s.P) * r.centre + Eigen::Vector3d(s.u[0], s.u[1], s.u[2]),
           (step_matrix(s.C) * r.centre).norm() + r.radius};
      f = s.parent;
    }
    out.push_back(r);
  }
  return out;
}

std::vector<unsigned char> links_far_from_scene(const RobotLayout& layout, const SceneGrid& grid,
                                                double distance) {
  std::vector<unsigned char> far;
  for (const LinkReach& r : link_reach(layout)) {
    const double rq = r.radius + distance;
    bool clear = !std::isinf(r.radius);
    if (clear && grid.clear(r.centre.data(), rq)) {  // the field's bound settles most
      far.push_back(1);
      continue;
    }
    for (std::size_t e = 0; clear && e < grid.elements().size(); ++e)
      clear = element_distance(grid.elements()[e], r.centre) > rq;
    far.push_back(clear ? 1 : 0);
  }
  return far;
}

}  // namespace medspheres::check::detail
