#include "support/mesh_writers.h"

#include <cstdint>
#include <cstring>
#include <sstream>
#include <utility>
#include <vector>

#include "medspheres/mesh/mesh_generators.h"

namespace medspheres::test {

namespace {

std::ostringstream precise() {
  std::ostringstream s;
  s.precision(17);
  return s;
}

Eigen::Vector3d normal_of(const TriangleMesh& m, std::size_t t) {
  const Eigen::Vector3d n =
      (m.corner(t, 1) - m.corner(t, 0)).cross(m.corner(t, 2) - m.corner(t, 0));
  return n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
}

std::string base64(const std::string& bytes) {
  static const char* a = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint8_t(bytes[i]) << 16) | (std::uint8_t(bytes[i + 1]) << 8) |
                            std::uint8_t(bytes[i + 2]);
    out += a[v >> 18];
    out += a[(v >> 12) & 63];
    out += a[(v >> 6) & 63];
    out += a[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const std::uint32_t v = std::uint8_t(bytes[i]) << 16;
    out += a[v >> 18];
    out += a[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const std::uint32_t v = (std::uint8_t(bytes[i]) << 16) | (std::uint8_t(bytes[i + 1]) << 8);
    out += a[v >> 18];
    out += a[(v >> 12) & 63];
    out += a[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

template <typename T>
void append(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

}  // namespace

std::string to_off(const TriangleMesh& m) {
  auto s = precise();
  s << "OFF\n" << m.vertices.size() << " " << m.triangles.size() << " 0\n";
  for (const auto& v : m.vertices) s << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : m.triangles) s << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return s.str();
}

std::string to_obj(const TriangleMesh& m, bool unwelded) {
  auto s = precise();
  s << "# generated\n";
  if (!unwelded) {
    for (const auto& v : m.vertices) s << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const auto& t : m.triangles)
      s << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  } else {
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const auto& v = m.corner(t, k);
        s << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
      }
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      s << "f " << 3 * t + 1 << " " << 3 * t + 2 << " " << 3 * t + 3 << "\n";
  }
  return s.str();
}

std::string to_stl_ascii(const TriangleMesh& m) {
  auto s = precise();
  s << "solid generated\n";
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Eigen::Vector3d n = normal_of(m, t);
    s << " facet normal " << n.x() << " " << n.y() << " " << n.z() << "\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const auto& v = m.corner(t, k);
      s << "   vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
    }
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid generated\n";
  return s.str();
}

std::string to_stl_binary(const TriangleMesh& m) {
  std::string s(80, ' ');
  s.replace(0, 9, "generated");
  append<std::uint32_t>(s, static_cast<std::uint32_t>(m.triangles.size()));
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Eigen::Vector3d n = normal_of(m, t);
    for (int i = 0; i < 3; ++i) append<float>(s, static_cast<float>(n[i]));
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) append<float>(s, static_cast<float>(m.corner(t, k)[i]));
    append<std::uint16_t>(s, 0);
  }
  return s;
}

std::string to_ply_ascii(const TriangleMesh& m) {
  auto s = precise();
  s << "ply\nformat ascii 1.0\nelement vertex " << m.vertices.size()
    << "\nproperty double x\nproperty double y\nproperty double z\nelement face "
    << m.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : m.vertices) s << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : m.triangles) s << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return s.str();
}

std::string to_dae(const TriangleMesh& m, const Eigen::Matrix4d& X) {
  auto s = precise();
  s << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="g" name="g"><mesh>
      <source id="g-pos"><float_array id="g-pos-array" count=")"
    << 3 * m.vertices.size() << "\">";
  for (const auto& v : m.vertices) s << v.x() << " " << v.y() << " " << v.z() << " ";
  s << R"(</float_array>
        <technique_common><accessor source="#g-pos-array" count=")"
    << m.vertices.size() << R"(" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="g-vtx"><input semantic="POSITION" source="#g-pos"/></vertices>
      <triangles count=")"
    << m.triangles.size() << R"("><input semantic="VERTEX" source="#g-vtx" offset="0"/><p>)";
  for (const auto& t : m.triangles) s << t[0] << " " << t[1] << " " << t[2] << " ";
  s << R"(</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="scene">
    <node id="n" name="n"><matrix>)";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) s << X(r, c) << " ";
  s << R"(</matrix><instance_geometry url="#g"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
  return s.str();
}

std::string to_gltf(const TriangleMesh& m, const std::vector<Eigen::Vector3d>& offsets) {
  std::string buf;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = Eigen::Vector3f::Constant(-1e30f);
  for (const auto& v : m.vertices) {
    const Eigen::Vector3f f = v.cast<float>();
    lo = lo.cwiseMin(f);
    hi = hi.cwiseMax(f);
    for (int i = 0; i < 3; ++i) append<float>(buf, f[i]);
  }
  const std::size_t pos_bytes = buf.size();
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) append<std::uint32_t>(buf, static_cast<std::uint32_t>(t[k]));
  const std::size_t idx_bytes = buf.size() - pos_bytes;
  auto s = precise();
  s << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[)";
  for (std::size_t i = 0; i < offsets.size(); ++i) s << (i ? "," : "") << i;
  s << R"(]}],"nodes":[)";
  for (std::size_t i = 0; i < offsets.size(); ++i)
    s << (i ? "," : "") << R"({"mesh":0,"translation":[)" << offsets[i].x() << "," << offsets[i].y()
      << "," << offsets[i].z() << "]}";
  s << R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":4}]}],)"
    << R"("buffers":[{"byteLength":)" << buf.size()
    << R"(,"uri":"data:application/octet-stream;base64,)" << base64(buf) << R"("}],)"
    << R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" << pos_bytes
    << R"(,"target":34962},{"buffer":0,"byteOffset":)" << pos_bytes << R"(,"byteLength":)"
    << idx_bytes << R"(,"target":34963}],)"
    << R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" << m.vertices.size()
    << R"(,"type":"VEC3","min":[)" << lo.x() << "," << lo.y() << "," << lo.z() << R"(],"max":[)"
    << hi.x() << "," << hi.y() << "," << hi.z() << R"(]},)"
    << R"({"bufferView":1,"componentType":5125,"count":)" << 3 * m.triangles.size()
    << R"(,"type":"SCALAR"}]})";
  return s.str();
}

TriangleMesh cube_mesh(double lo, double hi) {
  TriangleMesh m = make_box(Eigen::Vector3d::Constant((hi - lo) / 2));
  for (auto& v : m.vertices) v += Eigen::Vector3d::Constant((hi + lo) / 2);
  return m;
}

void append_mesh(TriangleMesh& to, const TriangleMesh& m, bool inward) {
  const int off = static_cast<int>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), m.vertices.begin(), m.vertices.end());
  for (auto t : m.triangles) {
    if (inward) std::swap(t[1], t[2]);
    to.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
  }
}

}  // namespace medspheres::test
