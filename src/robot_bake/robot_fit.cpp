// The fit of a robot's sphere file, link by link (robot_fit.h).
#include "medspheres/robot_bake/robot_fit.h"

#include <algorithm>
#include <cmath>

#include "medspheres/error.h"

namespace medspheres {

namespace {

bool is_primitive(const Sphere& s, const std::vector<Sphere>& primitives) {
  return std::any_of(primitives.begin(), primitives.end(), [&](const Sphere& p) {
    return (s.center - p.center).norm() <= 1e-6 * p.radius &&
           std::abs(s.radius - p.radius) <= 1e-6 * p.radius;
  });
}

}  // namespace

std::vector<LinkFit> evaluate_robot_fit(const std::vector<LinkSolid>& solids,
                                        const std::map<std::string, SphereSet>& spheres,
                                        const std::string& spheres_source,
                                        const FitOptions& options) {
  for (const auto& entry : spheres)
    if (std::none_of(solids.begin(), solids.end(),
                     [&](const LinkSolid& s) { return s.link == entry.first; }))
      throw InputError(spheres_source, "link '" + entry.first + "' is not a link of the robot");
  std::vector<LinkFit> fits;
  for (const LinkSolid& solid : solids) {
    LinkFit fit;
    fit.link = solid.link;
    const auto it = spheres.find(solid.link);
    std::vector<Sphere> measured;
    if (it != spheres.end()) {
      fit.spheres = it->second.size();
      for (const Sphere& s : it->second.spheres)
        if (is_primitive(s, solid.spheres))
          ++fit.primitives;
        else
          measured.push_back(s);
    }
    if (solid.empty()) {
      fit.note = "no collision geometry";
    } else if (solid.parts.empty()) {
      fit.note = "sphere primitives only";
    } else if (measured.empty()) {
      fit.note = "no spheres for its meshed parts";
    } else {
      const TriangleMesh mesh = solid.placed_mesh();
      fit.fit = evaluate_fit(mesh, measured, options);
      CoverCertificateOptions co;
      co.threads = options.threads;
      fit.certificate = certify_cover(mesh, it->second.spheres, co);
    }
    fits.push_back(std::move(fit));
  }
  return fits;
}

}  // namespace medspheres
