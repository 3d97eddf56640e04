#include "filled_inner.h"

#include <limits>

#include "medspheres/bake/bake_metadata.h"
#include "medspheres/bake/cover_record.h"
#include "medspheres/fcl/bounded_geometry.h"
#include "medspheres/mesh/cover_certificate.h"
#include "medspheres/mesh/filled_solid.h"
#include "medspheres/number_text.h"

namespace medspheres {

namespace {

// The bake of \p request on the filled solid of \p mesh at \p resolution.
BakeOutcome bake_on_filled(const TriangleMesh& mesh, const MeshReport& report,
                           const BakeRequest& request, const std::string& name,
                           const std::string& sha256, int resolution) {
  BakeRequest r = request;
  r.solid = SolidKind::kRobust;
  r.robust = filled_solid_options(report.largest_side(), resolution);
  r.robust_thickness.reset();
  return bake_mesh(mesh, report, r, name, sha256);
}

// Records on \p out that its set was baked on the filled solid (\p key: \p value, and the
// shell fraction) and warns of it; \p what says what the set then is.
void record_filled(BakeOutcome& out, const std::string& key, const std::string& value,
                   double fraction, const std::string& what) {
  out.record.extra_strings[key] = value;
  out.record.extra_stats["shell_fraction"] = fraction;
  out.spheres.metadata_json =
      out.cover ? cover_metadata_json(out.record) : bake_metadata_json(out.record);
  out.warnings.push_back("its solid is a thin shell (" + number_text(fraction, 3) +
                         " of its filled solid's volume): " + what);
}

}  // namespace

double fill_fraction(const TriangleMesh& mesh, const MeshReport& report, const BakeRequest& request,
                     const std::string& name) {
  if (request.solid != SolidKind::kAuto) return std::numeric_limits<double>::quiet_NaN();
  return shell_fraction(mesh, report, name);
}

std::optional<BakeOutcome> bake_filled_inner(const TriangleMesh& mesh, const MeshReport& report,
                                             const BakeRequest& request, const std::string& name,
                                             const std::string& sha256, double fraction) {
  if (request.solid != SolidKind::kAuto || request.method != BakeMethod::kMedial) return {};
  if (!is_thin_shell(fraction)) return {};
  BakeOutcome out = bake_on_filled(mesh, report, request, name, sha256, kFillResolution);
  record_filled(out, fcl::kInnerSolidKey, fcl::kInnerSolidFilled, fraction,
                "the inner set fills the filled solid (inner_solid filled), the covering set "
                "covers the real surface");
  return out;
}

std::optional<BakeOutcome> bake_filled_cover(const TriangleMesh& mesh, const MeshReport& report,
                                             const BakeRequest& request, const std::string& name,
                                             const std::string& sha256, double fraction,
                                             int resolution) {
  if (request.solid != SolidKind::kAuto || request.method != BakeMethod::kCover) return {};
  if (!is_thin_shell(fraction)) return {};
  BakeOutcome out = bake_on_filled(mesh, report, request, name, sha256, resolution);
  // bake_robust certified (and repaired) the cover on the mesh's own triangles and kept the
  // filled solid's certificate; what the robot file states is the real surface's.
  CoverCertificateOptions co;
  co.threads = request.medial.threads;
  out.cover->certificate = certify_cover(mesh, out.cover->spheres.spheres, co);
  record_filled(out, "cover_solid", "filled", fraction,
                "the covering set is baked on the filled solid (cover_solid filled) and "
                "certified on the real surface");
  return out;
}

}  // namespace medspheres
