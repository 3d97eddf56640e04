#include "medspheres/mesh_io.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <unordered_map>

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "medspheres/error.h"

namespace medspheres {

namespace {

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return e;
}

// Bit-exact welding key; -0.0 is folded onto +0.0.
struct PointKey {
  std::uint64_t bits[3];
  bool operator==(const PointKey& o) const {
    return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
  }
};
struct PointKeyHash {
  std::size_t operator()(const PointKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ull ^ (b >> 29);
    return static_cast<std::size_t>(h);
  }
};
PointKey key_of(const Eigen::Vector3d& p) {
  PointKey k;
  for (int i = 0; i < 3; ++i) {
    const double v = p[i] == 0.0 ? 0.0 : p[i];
    std::memcpy(&k.bits[i], &v, sizeof v);
  }
  return k;
}

class Welder {
 public:
  explicit Welder(TriangleMesh& mesh) : mesh_(mesh) {}
  int add(const Eigen::Vector3d& p) {
    // NaN compares unequal to itself, so never weld non-finite points; the usability
    // check reports them.
    if (!p.allFinite()) return push(p);
    auto [it, inserted] = index_.try_emplace(key_of(p), 0);
    if (inserted) it->second = push(p);
    return it->second;
  }

 private:
  int push(const Eigen::Vector3d& p) {
    mesh_.vertices.push_back(p);
    return static_cast<int>(mesh_.vertices.size() - 1);
  }
  TriangleMesh& mesh_;
  std::unordered_map<PointKey, int, PointKeyHash> index_;
};

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

LoadedMesh load_mesh(const std::string& path, const MeshLoadOptions& options) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "no such file");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a directory, not a mesh file");
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe)
      throw InputError(path, std::string("cannot open for reading: ") + std::strerror(errno));
  }
  if (fs::file_size(path, ec) == 0) throw InputError(path, "the file is empty");

  Assimp::Importer importer;
  const std::string ext = lower_extension(path);
  if (ext.empty() || !importer.IsExtensionSupported(ext)) {
    throw InputError(path, "unsupported mesh format '" + ext +
                               "' (use STL, OBJ, PLY, OFF, DAE, glTF/GLB or another format "
                               "assimp reads)");
  }
  // Drop point and line primitives; triangulate polygons. No vertex joining: welding is
  // done below on positions only, so that split normals or UVs do not split vertices.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Keep COLLADA coordinates as written: no Z-up to Y-up rotation (robot description
  // formats place DAE meshes in the file's own axes).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (scene == nullptr) {
    std::string why = importer.GetErrorString();
    if (why.empty()) why = "unknown error";
    throw InputError(path, "cannot parse the file: " + why);
  }

  LoadedMesh out;
  TriangleMesh& mesh = out.mesh;
  Welder welder(mesh);
  std::vector<char> referenced(scene->mNumMeshes, 0);

  auto add_mesh = [&](unsigned mesh_index, const Eigen::Matrix4d& X) {
    const aiMesh* m = scene->mMeshes[mesh_index];
    std::vector<int> ids(m->mNumVertices);
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      const aiVector3D& p = m->mVertices[v];
      const Eigen::Vector4d q = X * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
      ids[v] = welder.add(q.head<3>() / q.w());
    }
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      mesh.triangles.push_back(
          {ids[face.mIndices[0]], ids[face.mIndices[1]], ids[face.mIndices[2]]});
    }
  };

  std::function<void(const aiNode*, const Eigen::Matrix4d&)> walk =
      [&](const aiNode* node, const Eigen::Matrix4d& parent) {
        const Eigen::Matrix4d X = parent * to_eigen(node->mTransformation);
        for (unsigned i = 0; i < node->mNumMeshes; ++i) {
          const unsigned mi = node->mMeshes[i];
          if (mi >= scene->mNumMeshes) continue;
          referenced[mi] = 1;
          add_mesh(mi, X);
        }
        for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], X);
      };
  if (scene->mRootNode != nullptr) walk(scene->mRootNode, Eigen::Matrix4d::Identity());
  std::size_t orphans = 0;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    if (referenced[i]) continue;
    add_mesh(i, Eigen::Matrix4d::Identity());
    ++orphans;
  }
  if (orphans > 0)
    out.warnings.push_back(std::to_string(orphans) +
                           " mesh(es) not placed by any scene node were kept untransformed");

  check_mesh_usable(mesh, path);

  if (options.fix_orientation) {
    out.orientation_fix = orient_mesh(mesh);
    if (out.orientation_fix.triangles_flipped_for_consistency > 0)
      out.warnings.push_back("flipped " +
                             std::to_string(out.orientation_fix.triangles_flipped_for_consistency) +
                             " triangle(s) to make the winding of their component consistent");
    if (out.orientation_fix.components_flipped_outward > 0)
      out.warnings.push_back("flipped " +
                             std::to_string(out.orientation_fix.components_flipped_outward) +
                             " inward-wound closed component(s) to face outward");
  }
  out.report = analyze_mesh(mesh);
  if (!out.report.closed)
    out.warnings.push_back("the mesh is not closed (" + std::to_string(out.report.boundary_edges) +
                           " boundary edges, " + std::to_string(out.report.nonmanifold_edges) +
                           " non-manifold edges); its inside is defined by the generalized "
                           "winding number");
  if (out.report.degenerate_triangles > 0)
    out.warnings.push_back(std::to_string(out.report.degenerate_triangles) +
                           " degenerate (zero-area) triangle(s)");
  return out;
}

}  // namespace medspheres
