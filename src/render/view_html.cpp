#include "medspheres/render/view_html.h"

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "view_data.h"

namespace medspheres::render {

namespace assets {
extern const char* const kThreeModule;
extern const char* const kOrbitControlsModule;
extern const char* const kViewerHtml;
extern const char* const kViewerJs;
}  // namespace assets

namespace {

using Json = nlohmann::json;
using detail::base64;

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
  for (const ScenePart& part : scene.parts)
    data["parts"].push_back(detail::part_data(part, options));
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
