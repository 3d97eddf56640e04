// Link solids: each element's mesh in its own frame, and the placement into the link frame.
#include "medspheres/robot/link_solid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/number_text.h"
#include "medspheres/sha256.h"

namespace medspheres {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string exact(const Eigen::Vector3d& v) {
  return exact_number_text(v.x()) + " " + exact_number_text(v.y()) + " " + exact_number_text(v.z());
}

// The file's mesh with S applied; a mirroring scale (negative product) reverses the
// triangles so that they stay wound outward.
TriangleMesh scaled(const TriangleMesh& mesh, const Eigen::Vector3d& scale) {
  TriangleMesh out = mesh;
  for (Eigen::Vector3d& v : out.vertices) v = v.cwiseProduct(scale);
  if (scale.prod() < 0.0)
    for (auto& t : out.triangles) std::swap(t[1], t[2]);
  return out;
}

// Rounds a gap up past the few ulps its evaluation can lose.
double rounded_up(double gap, double radius) {
  return gap * (1.0 + 1e-9) + 1e-12 * radius;
}

// A capsule's mesh (make_capsule) is convex, holds its axis and has its vertices on the
// capsule. A point p of the true surface has a nearest axis point a; the ray from a
// through p leaves the mesh at q on a facet F, before p, and |q - a| >= the distance from
// a to F's plane. For a point of the side the ray is level and leaves through a side
// facet; for a point of a cap, a is that cap's end and the ray leaves through the cap. So
// |p - q| = radius - |q - a| <= radius - min over facets and axis ends of that distance.
double capsule_gap(const TriangleMesh& mesh, double radius, double half_length) {
  const Eigen::Vector3d ends[2] = {{0.0, 0.0, half_length}, {0.0, 0.0, -half_length}};
  double least = radius;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
    if (n.norm() == 0.0) continue;
    const Eigen::Vector3d u = n.normalized();
    for (const Eigen::Vector3d& e : ends) least = std::min(least, u.dot(a - e));
  }
  return rounded_up(radius - std::max(least, 0.0), radius);
}

LinkSolidPart primitive_part(const LinkPart& part) {
  LinkSolidPart out;
  out.origin = part.origin;
  if (part.shape == PartShape::kBox) {
    out.mesh = make_box(part.size / 2.0, 1);
    out.source = "box " + exact(part.size);
  } else if (part.shape == PartShape::kCapsule) {
    out.mesh = make_capsule(part.size.x(), part.size.z() / 2.0, kCylinderSlices, kCapsuleStacks);
    out.source =
        "capsule " + exact_number_text(part.size.x()) + " " + exact_number_text(part.size.z());
    out.surface_gap = capsule_gap(out.mesh, part.size.x(), part.size.z() / 2.0);
  } else {
    out.mesh = make_cylinder(part.size.x(), part.size.z() / 2.0, kCylinderSlices);
    out.source =
        "cylinder " + exact_number_text(part.size.x()) + " " + exact_number_text(part.size.z());
    // A point of the side is at most the sagitta from its facet; a point of a cap's disc
    // outside the inscribed polygon is at most the sagitta from the polygon's edge.
    const double r = part.size.x();
    out.surface_gap = rounded_up(r * (1.0 - std::cos(kPi / kCylinderSlices)), r);
  }
  out.key = out.source;
  return out;
}

struct LoadedFile {
  LoadedMesh loaded;
  std::string sha256;
};

const LoadedFile& load_once(std::map<std::string, LoadedFile>& cache, const std::string& path,
                            const MeshLoadOptions& options) {
  auto it = cache.find(path);
  if (it != cache.end()) return it->second;
  LoadedFile file{load_mesh(path, options), file_sha256(path)};
  return cache.emplace(path, std::move(file)).first->second;
}

}  // namespace

TriangleMesh LinkSolid::placed_mesh() const {
  TriangleMesh out;
  for (const LinkSolidPart& part : parts) {
    const int base = static_cast<int>(out.vertices.size());
    for (const Eigen::Vector3d& v : part.mesh.vertices) out.vertices.push_back(part.origin * v);
    for (const auto& t : part.mesh.triangles)
      out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return out;
}

double LinkSolid::surface_gap() const {
  double gap = 0.0;
  for (const LinkSolidPart& part : parts) gap = std::max(gap, part.surface_gap);
  return gap;
}

std::size_t LinkSolid::triangles() const {
  std::size_t n = 0;
  for (const LinkSolidPart& part : parts) n += part.mesh.num_triangles();
  return n;
}

std::vector<LinkSolid> load_link_solids(const UrdfRobot& robot, const MeshLoadOptions& options) {
  std::map<std::string, LoadedFile> cache;
  std::vector<LinkSolid> solids;
  for (const UrdfLink& link : robot.links) {
    LinkSolid solid;
    solid.link = link.name;
    for (const LinkPart& part : link.parts) {
      if (part.shape == PartShape::kSphere) {
        solid.spheres.push_back({part.origin.translation(), part.size.x()});
        continue;
      }
      if (part.shape != PartShape::kMesh) {
        solid.parts.push_back(primitive_part(part));
        continue;
      }
      try {
        const LoadedFile& file = load_once(cache, part.path, options);
        LinkSolidPart out;
        out.mesh = scaled(file.loaded.mesh, part.scale);
        out.origin = part.origin;
        out.source = part.path;
        out.sha256 = file.sha256;
        out.key = "mesh " + file.sha256 + " scale " + exact(part.scale);
        solid.parts.push_back(std::move(out));
      } catch (const InputError& e) {
        throw InputError(robot.path, "link '" + link.name + "': " + e.what());
      }
    }
    solids.push_back(std::move(solid));
  }
  return solids;
}

}  // namespace medspheres
