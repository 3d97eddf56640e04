#include "medspheres/measure/solid_choice.h"

#include <nlohmann/json.hpp>

namespace medspheres {

SolidChoice recorded_solid(const std::string& metadata_json) {
  SolidChoice c;
  const nlohmann::json meta = nlohmann::json::parse(metadata_json, nullptr, false);
  if (!meta.is_object() || !meta.contains("stats") || !meta["stats"].is_object()) return c;
  const nlohmann::json& st = meta["stats"];
  if (st.value("solid", std::string()) != to_string(SolidKind::kRobust)) return c;
  c.kind = SolidKind::kRobust;
  if (st.contains("robust_resolution") && st["robust_resolution"].is_number())
    c.robust.resolution = st["robust_resolution"].get<int>();
  if (st.contains("robust_thickness") && st["robust_thickness"].is_number())
    c.robust.thickness = st["robust_thickness"].get<double>();
  return c;
}

SolidChoice choose_solid(SolidKind requested, const RobustSolidOptions& robust,
                         bool robust_explicit, const std::string& metadata_json) {
  const SolidChoice recorded = recorded_solid(metadata_json);
  switch (requested) {
    case SolidKind::kAuto:
      return recorded;
    case SolidKind::kWinding:
      return {};
    case SolidKind::kRobust:
      break;
  }
  SolidChoice c{SolidKind::kRobust, robust};
  if (!robust_explicit && recorded.kind == SolidKind::kRobust) c.robust = recorded.robust;
  return c;
}

void check_solid_request(const SolidRequest& request) {
  validate(request.robust);
  check_length(request.robust_thickness, "robust_thickness", true);
}

SolidChoice eval_solid(const SolidRequest& request, double longest,
                       const std::string& metadata_json) {
  check_solid_request(request);
  const RobustSolidOptions defaults;
  RobustSolidOptions robust = request.robust;
  if (request.robust_thickness) robust.thickness = request.robust_thickness->in(longest);
  const bool robust_explicit = request.robust_thickness ||
                               request.robust.resolution != defaults.resolution ||
                               request.robust.thickness != defaults.thickness;
  return choose_solid(request.kind, robust, robust_explicit, metadata_json);
}

TriangleMesh solid_mesh(const TriangleMesh& mesh, const SolidChoice& choice,
                        const std::string& name) {
  if (choice.kind != SolidKind::kRobust) return mesh;
  return make_robust_solid(mesh, choice.robust, name).mesh;
}

}  // namespace medspheres
