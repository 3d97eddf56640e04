#include "view_data.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "medspheres/mesh/cover_certificate.h"

namespace medspheres::render::detail {

namespace {

// A typed array as the page reads it: its bytes, little-endian, in base64.
template <class T>
std::string packed(const std::vector<T>& values) {
  std::string bytes(values.size() * sizeof(T), '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint64_t u = 0;
    std::memcpy(&u, &values[i], sizeof(T));
    for (std::size_t b = 0; b < sizeof(T); ++b)
      bytes[sizeof(T) * i + b] = static_cast<char>((u >> (8 * b)) & 0xff);
  }
  return base64(bytes);
}

// Points of the part's box as 16-bit integers (view_data.h).
struct Quantizer {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), scale = Eigen::Vector3d::Zero();

  explicit Quantizer(const Eigen::AlignedBox3d& box) {
    if (box.isEmpty()) return;
    lo = box.min();
    for (int k = 0; k < 3; ++k) {
      const double side = box.max()[k] - box.min()[k];
      scale[k] = side > 0.0 ? kQuantSteps / side : 0.0;
    }
  }
  void push(std::vector<std::uint16_t>& out, const Eigen::Vector3d& p) const {
    for (int k = 0; k < 3; ++k) {
      const double q = std::round((p[k] - lo[k]) * scale[k]);
      out.push_back(static_cast<std::uint16_t>(std::min(std::max(q, 0.0), kQuantSteps)));
    }
  }
};

std::string spheres_data(const std::vector<Sphere>& spheres) {
  std::vector<float> out;
  for (const Sphere& s : spheres) {
    for (int k = 0; k < 3; ++k) out.push_back(static_cast<float>(s.center[k]));
    out.push_back(static_cast<float>(s.radius));
  }
  return packed(out);
}

bool whole(const TriangleMesh& mesh, const CoverPiece& p) {
  for (int k = 0; k < 3; ++k)
    if (p.corners[k] != mesh.corner(static_cast<std::size_t>(p.triangle), k)) return false;
  return true;
}

// What certify_cover leaves uncertified: a bit per triangle uncertified as a whole, the
// corners of smaller pieces; an uncertified triangle whose pieces were not all listed is
// marked whole.
nlohmann::json uncovered_data(const TriangleMesh& mesh, const std::vector<Sphere>& balls,
                              const Quantizer& quant, const ViewOptions& options) {
  std::vector<std::uint8_t> bits((mesh.num_triangles() + 7) / 8, 0);
  std::vector<std::uint16_t> pieces;
  auto mark = [&bits](std::size_t t) { bits[t / 8] |= static_cast<std::uint8_t>(1u << (t % 8)); };
  if (!balls.empty() && !mesh.triangles.empty()) {
    CoverCertificateOptions o;
    o.max_depth = options.cover_depth;
    o.max_pieces_reported = 2000000;
    o.max_worst_evaluations = 1;  // the worst point is not shown
    o.threads = options.threads;
    const CoverCertificate cert = certify_cover(mesh, balls, o);
    int last_listed = -1;
    for (const CoverPiece& p : cert.uncertified_pieces) {
      if (whole(mesh, p))
        mark(static_cast<std::size_t>(p.triangle));
      else
        for (const Eigen::Vector3d& c : p.corners) quant.push(pieces, c);
      last_listed = p.triangle;
    }
    if (cert.uncertified_pieces.size() < cert.uncertified_pieces_total)
      for (std::size_t t = static_cast<std::size_t>(last_listed + 1); t < mesh.num_triangles(); ++t)
        if (!cert.triangle_certified[t]) mark(t);
  }
  return {{"whole", packed(bits)}, {"pieces", packed(pieces)}};
}

}  // namespace

std::string base64(const std::string& bytes) {
  static const char* const kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    unsigned v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

nlohmann::json part_data(const ScenePart& part, const ViewOptions& options) {
  const TriangleMesh& mesh = part.mesh;
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& v : mesh.vertices) box.extend(v);
  const Quantizer quant(box);
  std::vector<std::uint16_t> positions;
  for (const Eigen::Vector3d& v : mesh.vertices) quant.push(positions, v);
  nlohmann::json j;
  j["name"] = part.name;
  j["triangle_count"] = mesh.num_triangles();
  j["vertex_count"] = mesh.vertices.size();
  j["box"] = nlohmann::json::array();
  for (int k = 0; k < 6; ++k)
    j["box"].push_back(box.isEmpty() ? 0.0 : (k < 3 ? box.min() : box.max())[k % 3]);
  j["positions"] = packed(positions);
  const bool narrow = mesh.vertices.size() <= 65536;
  j["index_bytes"] = narrow ? 2 : 4;
  std::vector<std::uint16_t> narrow_indices;
  std::vector<std::uint32_t> wide_indices;
  for (const auto& t : mesh.triangles)
    for (int k : t)
      narrow ? narrow_indices.push_back(static_cast<std::uint16_t>(k))
             : wide_indices.push_back(static_cast<std::uint32_t>(k));
  j["triangles"] = narrow ? packed(narrow_indices) : packed(wide_indices);
  j["inner"] = spheres_data(part.inner);
  j["outer"] = spheres_data(part.outer);
  j["uncovered_inner"] = uncovered_data(mesh, part.inner, quant, options);
  j["uncovered_outer"] = uncovered_data(mesh, part.outer, quant, options);
  return j;
}

}  // namespace medspheres::render::detail
