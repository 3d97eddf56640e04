// Protrusion weights (protrusion_weights.h): a box whose +x face is a contact region gets
// balls that stick out less there than elsewhere and less than the unweighted cover's
// there, measured by the box's closed-form signed distance and a scan of the region's
// points; the certificate holds.
#include <algorithm>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "medspheres/cover/cover.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/mesh/mesh_query.h"
#include "support/cover_solids.h"

using namespace medspheres;

namespace {

const Eigen::Vector3d kHalf(1.0, 0.6, 0.4);

// Signed distance to the box's surface, positive inside (closed form).
double box_depth(const Eigen::Vector3d& c) {
  const Eigen::Vector3d q = c.cwiseAbs() - kHalf;
  if ((q.array() <= 0.0).all()) return -q.maxCoeff();
  return -q.cwiseMax(0.0).norm();
}

// Points on the +x face, every 0.05.
std::vector<Eigen::Vector3d> contact_face() {
  std::vector<Eigen::Vector3d> out;
  for (double y = -kHalf.y(); y <= kHalf.y() + 1e-9; y += 0.05)
    for (double z = -kHalf.z(); z <= kHalf.z() + 1e-9; z += 0.05) out.emplace_back(kHalf.x(), y, z);
  return out;
}

constexpr double kReach = 0.02;

struct Split {
  double contact = 0.0, rest = 0.0;  // largest protrusion of the balls reaching the face, others
};

// A ball reaches the face when a face point is within its radius plus kReach; protrusion
// r - D(c) by the closed form.
Split protrusions(const std::vector<Sphere>& balls) {
  const std::vector<Eigen::Vector3d> face = contact_face();
  Split s;
  for (const Sphere& b : balls) {
    const bool on_face = std::any_of(face.begin(), face.end(), [&](const Eigen::Vector3d& p) {
      return (p - b.center).norm() <= b.radius + kReach;
    });
    double& into = on_face ? s.contact : s.rest;
    into = std::max(into, b.radius - box_depth(b.center));
  }
  return s;
}

}  // namespace

TEST_CASE("bake_cover: weights make the balls over a contact region stick out less", "[cover]") {
  const TriangleMesh box = make_box(kHalf, 3);
  const MeshQuery query(box);
  CoverOptions weighted;
  weighted.weights = {contact_face(), kReach, 4.0};
  const CoverResult plain = bake_cover(query, 32), tight = bake_cover(query, 32, weighted);
  CHECK(tight.certificate.certified);
  CHECK(tight.spheres.size() <= 32);
  CHECK(test::sampled_gap(box, tight.spheres.spheres) == 0.0);
  const Split p = protrusions(plain.spheres.spheres), t = protrusions(tight.spheres.spheres);
  INFO("plain: contact " << p.contact << " rest " << p.rest << "; weighted: contact " << t.contact
                         << " rest " << t.rest);
  CHECK(t.contact < 0.6 * p.contact);
  CHECK(t.contact < 0.5 * t.rest);
  // The protrusion the cover reports is the largest, the rest's.
  CHECK(tight.stats.max_protrusion == Approx(std::max(t.contact, t.rest)).epsilon(1e-6));
}

TEST_CASE("bake_cover: inactive weights change nothing, bad weights are refused", "[cover]") {
  const MeshQuery query(make_box(kHalf, 2));
  CoverOptions unit;
  unit.weights = {contact_face(), 0.05, 1.0};  // weight 1: inactive
  test::check_same_spheres(bake_cover(query, 8).spheres.spheres,
                           bake_cover(query, 8, unit).spheres.spheres);
  CoverOptions bad;
  bad.weights = {contact_face(), -1.0, 4.0};
  CHECK_THROWS_WITH(bake_cover(query, 8, bad), Catch::Contains("weights.reach"));
  bad.weights = {contact_face(), 0.1, 0.5};
  CHECK_THROWS_WITH(bake_cover(query, 8, bad), Catch::Contains("weights.weight"));
}
