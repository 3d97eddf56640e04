#pragma once
// RobotLayout: a robot made ready for the batched kernel. Links fixed to one another share
// a frame (fixed joints are folded into constants), the base pose is folded into the
// joints next to the root, and every link's spheres are stored in its frame, in arrays of
// structures of one coordinate each, level after level.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "medspheres/robot_model.h"

namespace medspheres::check::detail {

/// The sets of a link, in the order the certified mode walks them. kSpheres is the set the
/// spheres-only mode uses (the planner's covering set, or its inner set for a link that
/// has no covering set), a copy of kOuter or kInner.
enum Level : int { kOuter = 0, kInner = 1, kFineOuter = 2, kFineInner = 3, kLevels = 4 };

/// A moving joint: the frame it poses from its parent frame (0: fixed to W). Revolute:
/// R_PF = P + cos(q) C + sin(q) S, p_PF = u. Prismatic: R_PF = P, p_PF = u + q v. Then
/// X_WF = X_WP X_PF, rows of R first, row-major, then the translation.
struct FrameStep {
  int frame = 0, parent = 0;
  bool prismatic = false;
  int source = 0;  // index into q
  double multiplier = 1.0, offset = 0.0;
  double P[9] = {}, C[9] = {}, S[9] = {}, u[3] = {}, v[3] = {};
  // Revolute: P, C, S and u rounded to floats (the float pass's transform).
  float Pf[9] = {}, Cf[9] = {}, Sf[9] = {}, uf[3] = {};
};

/// A FrameStep's row-major 3 x 3 (P, C or S) as a matrix.
inline Eigen::Matrix3d step_matrix(const double* m) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = m[3 * r + c];
  return out;
}

struct LinkLayout {
  int frame = 0;
  double bound[4] = {};  // x, y, z, r in the frame: contains every sphere of every level
  std::uint32_t begin[kLevels] = {}, count[kLevels] = {};  // into RobotLayout's spheres
  Level spheres = kOuter;                                  // the spheres-only mode's set
};

struct RobotLayout {
  std::size_t dof = 0;
  int frames = 1;
  std::vector<FrameStep> steps;
  std::vector<LinkLayout> links;              // the links with geometry
  std::vector<std::string> link_names;        // of those links
  std::vector<double> x, y, z, r;             // every sphere, in its link's frame
  std::vector<std::uint32_t> pair_a, pair_b;  // self pairs, indices into links, a < b
  double max_radius = 0.0;                    // over every sphere
  double extent = 0.0;                        // largest |coordinate| + radius in any frame
  bool fine = false;
  std::vector<std::string> joint_names;  // the actuated joints, in q's order
};

/// \p planner: the planner's sets; \p fine: the larger sets of the same robot (may be
/// null). Self pairs: every two links with geometry but the two links of a joint and the
/// pairs \p disabled (names, either order).
/// \throws InputError (source "robot checker") for a fine model whose links or joints
/// are not the planner's, a disabled pair naming an unknown link, or inner points naming an
/// unknown link or a link without a covering set, or not finite, or of a radius < 0.
/// \p inner_points: spheres (radius >= 0) added to the planner's inner set of their links
/// (CheckerOptions::inner_points).
RobotLayout make_layout(const RobotModel& planner, const RobotModel* fine,
                        const Eigen::Isometry3d& X_WB,
                        const std::vector<std::pair<std::string, std::string>>& disabled,
                        const std::map<std::string, std::vector<Sphere>>& inner_points = {});

}  // namespace medspheres::check::detail
