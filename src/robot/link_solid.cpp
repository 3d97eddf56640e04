// Link solids: each element's mesh in its own frame, and the placement into the link frame.
#include "medspheres/robot/link_solid.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <utility>

#include "medspheres/error.h"
#include "medspheres/mesh/mesh_generators.h"
#include "medspheres/number_text.h"

namespace medspheres {

namespace {

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
  } else {
    out.mesh = make_cylinder(part.size.x(), part.size.z() / 2.0, kCylinderSlices);
    out.source =
        "cylinder " + exact_number_text(part.size.x()) + " " + exact_number_text(part.size.z());
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
