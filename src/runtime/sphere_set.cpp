#include "medspheres/sphere_set.h"

#include <cmath>
#include <sstream>

#include "medspheres/error.h"

namespace medspheres {

Eigen::AlignedBox3d SphereSet::bounds() const {
  Eigen::AlignedBox3d box;  // default-constructed: empty
  for (const Sphere& s : spheres) {
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(s.radius);
    box.extend(s.center - r);
    box.extend(s.center + r);
  }
  return box;
}

// The bounding box must be finite (|centre coordinate| + radius finite) so that nothing
// computed from the box overflows to infinity.
void validate_sphere_set(const SphereSet& set, const std::string& source, bool allow_points) {
  for (std::size_t i = 0; i < set.spheres.size(); ++i) {
    const Sphere& s = set.spheres[i];
    if (!s.center.allFinite()) {
      std::ostringstream msg;
      msg << "sphere " << i << " has a non-finite centre (" << s.center.x() << ", " << s.center.y()
          << ", " << s.center.z() << ")";
      throw InputError(source, msg.str());
    }
    if (!std::isfinite(s.radius) || !(s.radius > 0.0 || (allow_points && s.radius == 0.0))) {
      std::ostringstream msg;
      msg << "sphere " << i << " has radius " << s.radius << " (must be finite and "
          << (allow_points ? ">= 0)" : "> 0)");
      throw InputError(source, msg.str());
    }
    if (!(s.center.cwiseAbs().array() + s.radius).allFinite()) {
      std::ostringstream msg;
      msg << "sphere " << i << " (centre (" << s.center.x() << ", " << s.center.y() << ", "
          << s.center.z() << "), radius " << s.radius
          << ") reaches beyond the largest finite double";
      throw InputError(source, msg.str());
    }
  }
}

}  // namespace medspheres
