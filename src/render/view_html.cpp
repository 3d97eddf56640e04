#include "medspheres/render/view_html.h"

#include <cstdint>
#include <cstring>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "medspheres/mesh/cover_certificate.h"

namespace medspheres::render {

namespace assets {
extern const char* const kThreeModule;
extern const char* const kOrbitControlsModule;
extern const char* const kViewerHtml;
extern const char* const kViewerJs;
}  // namespace assets

namespace {

using Json = nlohmann::json;

// RFC 4648 base64, for the data: URLs of the import map.
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

// Coordinates as floats: a picture needs no more, and the page stays small.
void push_point(Json& out, const Eigen::Vector3d& p) {
  for (int k = 0; k < 3; ++k) out.push_back(static_cast<float>(p[k]));
}

void push_point(std::vector<float>& out, const Eigen::Vector3d& p) {
  for (int k = 0; k < 3; ++k) out.push_back(static_cast<float>(p[k]));
}

// A typed array for the page: its bytes, little-endian, in base64 (viewer.js decodes it
// into a Float32Array or an Int32Array).
template <class T>
std::string packed(const std::vector<T>& values) {
  static_assert(sizeof(T) == 4, "4-byte values");
  std::string bytes(values.size() * 4, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint32_t u = 0;
    std::memcpy(&u, &values[i], 4);
    for (int b = 0; b < 4; ++b) bytes[4 * i + b] = static_cast<char>((u >> (8 * b)) & 0xff);
  }
  return base64(bytes);
}

Json spheres_json(const std::vector<Sphere>& spheres) {
  Json out = Json::array();
  for (const Sphere& s : spheres) {
    Json row = Json::array();
    push_point(row, s.center);
    row.push_back(static_cast<float>(s.radius));
    out.push_back(std::move(row));
  }
  return out;
}

// The corners of the pieces certify_cover leaves uncertified, 9 numbers a piece; an
// uncertified triangle whose pieces were not all listed is added whole.
std::string uncovered_pieces(const TriangleMesh& mesh, const std::vector<Sphere>& balls,
                             const ViewOptions& options) {
  std::vector<float> out;
  if (balls.empty() || mesh.triangles.empty()) return packed(out);
  CoverCertificateOptions o;
  o.max_depth = options.cover_depth;
  o.max_pieces_reported = 2000000;
  o.max_worst_evaluations = 1;  // the worst point is not shown
  o.threads = options.threads;
  const CoverCertificate cert = certify_cover(mesh, balls, o);
  int last_listed = -1;
  for (const CoverPiece& p : cert.uncertified_pieces) {
    for (const Eigen::Vector3d& c : p.corners) push_point(out, c);
    last_listed = p.triangle;
  }
  if (cert.uncertified_pieces.size() < cert.uncertified_pieces_total)
    for (std::size_t t = static_cast<std::size_t>(last_listed + 1); t < mesh.num_triangles(); ++t)
      if (!cert.triangle_certified[t])
        for (int k = 0; k < 3; ++k) push_point(out, mesh.corner(t, k));
  return packed(out);
}

Json part_json(const ScenePart& part, const ViewOptions& options) {
  Json j;
  j["name"] = part.name;
  std::vector<float> positions;
  std::vector<std::int32_t> triangles;
  for (const Eigen::Vector3d& v : part.mesh.vertices) push_point(positions, v);
  for (const auto& t : part.mesh.triangles)
    for (int k : t) triangles.push_back(k);
  j["triangle_count"] = part.mesh.num_triangles();
  j["positions"] = packed(positions);
  j["triangles"] = packed(triangles);
  j["inner"] = spheres_json(part.inner);
  j["outer"] = spheres_json(part.outer);
  j["uncovered_inner"] = uncovered_pieces(part.mesh, part.inner, options);
  j["uncovered_outer"] = uncovered_pieces(part.mesh, part.outer, options);
  return j;
}

// JSON inside <script>: "</" would end the element early; "<\/" is the same JSON string.
std::string script_safe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// Replaces \p marker, searched from \p from on; returns the end of the inserted text.
std::size_t replace_marker(std::string& page, std::size_t from, const std::string& marker,
                           const std::string& text) {
  const std::size_t at = page.find(marker, from);
  if (at == std::string::npos) throw std::logic_error("viewer.html lacks " + marker);
  page.replace(at, marker.size(), text);
  return at + text.size();
}

}  // namespace

std::string view_html(const Scene& scene, const ViewOptions& options) {
  if (options.cover_depth < 0 || options.cover_depth > 10)
    throw std::invalid_argument("view_html: cover_depth must be 0 .. 10");
  Json data;
  data["title"] = options.title;
  data["warning"] = options.warning;
  data["parts"] = Json::array();
  for (const ScenePart& part : scene.parts) data["parts"].push_back(part_json(part, options));
  const Json imports = {
      {"imports",
       {{"three", "data:text/javascript;base64," + base64(assets::kThreeModule)},
        {"three/addons/controls/OrbitControls.js",
         "data:text/javascript;base64," + base64(assets::kOrbitControlsModule)}}}};
  std::string page = assets::kViewerHtml;
  // The markers in page order, each searched after the text inserted before it.
  std::size_t at = replace_marker(page, 0, "@TITLE@", html_escape(options.title));
  at = replace_marker(page, at, "@IMPORTMAP@", imports.dump());
  at = replace_marker(page, at, "@DATA@", script_safe(data.dump()));
  replace_marker(page, at, "@VIEWER_JS@", script_safe(assets::kViewerJs));
  return page;
}

}  // namespace medspheres::render
