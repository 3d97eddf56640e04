#include "medspheres/mesh/filled_solid.h"

#include <cmath>
#include <limits>

namespace medspheres {

RobustSolidOptions filled_solid_options(double longest, int resolution) {
  RobustSolidOptions options;
  options.resolution = resolution;
  options.thickness = kFillThickness * longest;
  options.escalate = false;
  return options;
}

RobustSolid make_filled_solid(const TriangleMesh& mesh, const std::string& name, int resolution) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& v : mesh.vertices) box.extend(v);
  const double longest = mesh.vertices.empty() ? 0.0 : box.sizes().maxCoeff();
  return make_robust_solid(mesh, filled_solid_options(longest, resolution), name);
}

double shell_fraction(const TriangleMesh& mesh, const MeshReport& report, const std::string& name) {
  double volume = report.signed_volume;
  if (!report.is_closed_outward()) {
    TriangleMesh centred = mesh;
    const Eigen::Vector3d centre = 0.5 * (report.bbox_min + report.bbox_max);
    for (Eigen::Vector3d& v : centred.vertices) v -= centre;
    volume = analyze_mesh(centred).signed_volume;
  }
  if (!(volume > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const RobustSolid filled = make_filled_solid(mesh, name, kFillProbeResolution);
  return volume / analyze_mesh(filled.mesh).signed_volume;
}

bool is_thin_shell(double fraction) {
  return std::isfinite(fraction) && fraction > 0.0 && fraction < kThinShellFraction;
}

bool is_thin_shell(double real_volume, double filled_volume) {
  if (!(filled_volume > 0.0)) return false;
  return is_thin_shell(real_volume / filled_volume);
}

}  // namespace medspheres
