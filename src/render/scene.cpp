#include "medspheres/render/scene.h"

#include <stdexcept>

#include "medspheres/mesh/mesh_generators.h"

namespace medspheres::render {

namespace {

void append_mesh(TriangleMesh& out, const TriangleMesh& mesh, const Eigen::Isometry3d& X) {
  const int base = static_cast<int>(out.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices) out.vertices.push_back(X * v);
  for (const auto& t : mesh.triangles)
    out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

void append_spheres(std::vector<Sphere>& out, const std::vector<Sphere>& spheres,
                    const Eigen::Isometry3d& X) {
  for (const Sphere& s : spheres) out.push_back({X * s.center, s.radius});
}

// A link's solid in its frame L: the placed parts and its sphere elements as icospheres
// (inscribed: their vertices lie on the sphere).
TriangleMesh link_mesh(const LinkSolid& solid) {
  TriangleMesh mesh = solid.placed_mesh();
  for (const Sphere& s : solid.spheres)
    append_mesh(mesh, make_icosphere(s.radius, 3),
                Eigen::Isometry3d(Eigen::Translation3d(s.center)));
  return mesh;
}

}  // namespace

Scene mesh_scene(const TriangleMesh& mesh, const SphereSet& inner, const SphereSet& outer) {
  Scene scene;
  scene.parts.push_back({"", mesh, inner.spheres, outer.spheres, Eigen::Isometry3d::Identity()});
  return scene;
}

Scene robot_scene(const RobotModel& model, const std::vector<Eigen::Isometry3d>& X_WL,
                  const std::vector<LinkSolid>& solids,
                  const std::map<std::string, LinkSpheres>& spheres, const std::string& source) {
  // Solids come from the same URDF as the model: every one has its link.
  if (X_WL.size() != model.links.size())
    throw std::invalid_argument("robot_scene: one pose per link is needed");
  Scene scene;
  std::string unknown;
  for (const auto& [name, sets] : spheres)
    if (model.find_link(name) == nullptr) unknown += (unknown.empty() ? "" : ", ") + name;
  if (!unknown.empty())
    scene.warnings.push_back(source +
                             ": spheres of links the robot does not have, left out: " + unknown);
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    const std::string& name = model.links[i].name;
    ScenePart part;
    part.name = name;
    part.pose = X_WL[i];
    for (const LinkSolid& s : solids)
      if (s.link == name) append_mesh(part.mesh, link_mesh(s), X_WL[i]);
    if (const auto it = spheres.find(name); it != spheres.end()) {
      append_spheres(part.inner, it->second.inner.spheres, X_WL[i]);
      append_spheres(part.outer, it->second.outer.spheres, X_WL[i]);
    }
    if (part.mesh.triangles.empty() && part.inner.empty() && part.outer.empty()) continue;
    scene.parts.push_back(std::move(part));
  }
  return scene;
}

TriangleMesh merged_mesh(const Scene& scene) {
  TriangleMesh out;
  for (const ScenePart& p : scene.parts) append_mesh(out, p.mesh, Eigen::Isometry3d::Identity());
  return out;
}

SphereSet merged_spheres(const Scene& scene, SetChoice choice) {
  SphereSet out;
  for (const ScenePart& p : scene.parts) {
    const bool outer =
        choice == SetChoice::outer || (choice == SetChoice::automatic && !p.outer.empty());
    append_spheres(out.spheres, outer ? p.outer : p.inner, Eigen::Isometry3d::Identity());
  }
  return out;
}

}  // namespace medspheres::render
