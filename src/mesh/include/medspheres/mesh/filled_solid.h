#pragma once
/// \file
/// The filled solid of a thin-walled mesh: the solid a robotics user means by a link whose
/// material is a thin shell around a cavity (a wrist housing open at one end, a pelvis
/// cover): the link closed, with its cavity filled.
///
/// Definition. The filled solid of a mesh of largest box side L is its robust solid
/// (robust_solid.h) at wall thickness t = kFillThickness L and resolution kFillResolution,
/// without escalation: the walls thickened by t, the outside flooded, and
/// what the thickness added within t of the outside taken back. That is a closing by a ball
/// of radius about t: every cavity whose opening is narrower than about 2 t is plugged by a
/// cap the ball rolls over, and concave parts narrower than that fill too. Like every robust
/// solid it is closed and outward wound, contains the mesh's surface and lies within
/// r + sqrt(3) h of it (r, h: RobustSolid::wall_radius, cell).
///
/// When it is used (is_thin_shell, by `robot --fill`): when the mesh's own solid fills less
/// than kThinShellFraction of the filled solid's volume (shell_fraction). On the Unitree G1
/// the four wrist roll and yaw links (0.079 to 0.082), the pelvis contour (0.050) and the
/// logo (0.053) are thin shells; every other link fills at least 0.24 of its filled solid
/// (docs/robots.md, "Thin shells").
///
/// Contract. An inner set baked on the filled solid lies inside the filled solid, not
/// inside the thin real material: its balls may sit in the cavity. It bounds the filled
/// solid, never the real one; a covering set is always certified on the real surface.

#include <string>

#include "medspheres/mesh/mesh_report.h"
#include "medspheres/mesh/robust_solid.h"
#include "medspheres/triangle_mesh.h"

namespace medspheres {

/// t of the filled solid, as a fraction of L.
inline constexpr double kFillThickness = 0.5;

/// A mesh is a thin shell when its volume is less than this fraction of its filled solid's.
inline constexpr double kThinShellFraction = 0.2;

/// The filled solid's resolution: cells of L / 48, so that it sticks out of the mesh's
/// convex parts by less than (1 + sqrt(3)/2 + sqrt(3)) L / 48 = 0.075 L (robust_solid.h).
/// The triangle budget's search (resolution 0: up to six grids, padded by the thickness)
/// costs 1.2 to 1.8 times the CPU of a 32-sphere bake on the G1's thin links, for the same
/// nerr within 0.003.
inline constexpr int kFillResolution = 48;

/// The resolution of the filled solid that `robot --fill-covers` bakes a thin shell's
/// covering set on: a cover's outward excess adds to the filled solid's, and the G1's
/// pelvis shell and hip roll links sit 2 to 5 mm apart, so the filled solid must stick out
/// of the pelvis shell (L = 0.136 m) by far less than the 0.075 L = 10 mm of
/// kFillResolution. At 96, partners meet the G1's filled solids in 66 of 10^4 free
/// configurations (702 at 48, 37 at 160), and the G1's six thin links' covers on it cost
/// about 7 s of CPU more than on their thin material (docs/self-collision.md, "Covers of
/// thin shells").
inline constexpr int kFillCoverResolution = 96;

/// The coarser resolution the thin-shell test (shell_fraction) builds the filled solid at:
/// every link of a robot is tested, few are filled.
inline constexpr int kFillProbeResolution = 32;

/// The options of the filled solid of a mesh whose largest box side is \p longest, at
/// \p resolution.
RobustSolidOptions filled_solid_options(double longest, int resolution = kFillResolution);

/// The filled solid of \p mesh (file comment) at \p resolution; \p name names it in
/// errors.
/// \throws as make_robust_solid.
RobustSolid make_filled_solid(const TriangleMesh& mesh, const std::string& name,
                              int resolution = kFillResolution);

/// The fraction of its filled solid (at kFillProbeResolution) that \p mesh fills: its
/// volume over the filled solid's; NaN when that volume is not positive. The volume of a
/// closed, outward mesh (\p report: analyze_mesh of it) is exact; of another mesh, its
/// signed volume about the centre of its box, indicative (exact once its gaps close).
/// \throws as make_robust_solid.
double shell_fraction(const TriangleMesh& mesh, const MeshReport& report, const std::string& name);

/// Whether a solid of volume \p real_volume is a thin shell within its filled solid of
/// volume \p filled_volume: real_volume < kThinShellFraction filled_volume (false for a
/// volume that is not positive or not finite).
bool is_thin_shell(double real_volume, double filled_volume);
/// Whether a shell_fraction is below kThinShellFraction (false for NaN).
bool is_thin_shell(double fraction);

}  // namespace medspheres
