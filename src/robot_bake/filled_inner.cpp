#include "filled_inner.h"

#include "medspheres/bake/bake_metadata.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/mesh/filled_solid.h"
#include "medspheres/number_text.h"

namespace medspheres {

std::optional<BakeOutcome> bake_filled_inner(const TriangleMesh& mesh, const MeshReport& report,
                                             const BakeRequest& request, const std::string& name,
                                             const std::string& sha256) {
  if (request.solid != SolidKind::kAuto || request.method != BakeMethod::kMedial) return {};
  const double fraction = shell_fraction(mesh, report, name);
  if (!is_thin_shell(fraction)) return {};
  BakeRequest r = request;
  r.solid = SolidKind::kRobust;
  r.robust = filled_solid_options(report.largest_side());
  r.robust_thickness.reset();
  BakeOutcome out = bake_mesh(mesh, report, r, name, sha256);
  out.record.extra_strings[fcl::kInnerSolidKey] = fcl::kInnerSolidFilled;
  out.record.extra_stats["shell_fraction"] = fraction;
  out.spheres.metadata_json = bake_metadata_json(out.record);
  out.warnings.push_back("its solid is a thin shell (" + number_text(fraction, 3) +
                         " of its filled solid's volume): the inner set fills the filled solid "
                         "(inner_solid filled), the covering set covers the real surface");
  return out;
}

}  // namespace medspheres
