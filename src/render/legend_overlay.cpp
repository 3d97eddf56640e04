#include "medspheres/render/legend_overlay.h"

#include <algorithm>
#include <sstream>
#include <utility>
#include <vector>

#include "medspheres/render/bitmap_font.h"

namespace medspheres::render {

namespace {

// \p text broken at spaces into lines of at most \p columns characters (a longer word is
// cut).
std::vector<std::string> wrap(const std::string& text, std::size_t columns) {
  std::vector<std::string> lines;
  std::stringstream in(text);
  for (std::string para; std::getline(in, para);) {
    std::string line;
    std::stringstream words(para);
    for (std::string w; words >> w;) {
      while (w.size() > columns) {
        if (!line.empty()) lines.push_back(line), line.clear();
        lines.push_back(w.substr(0, columns));
        w = w.substr(columns);
      }
      if (!line.empty() && line.size() + 1 + w.size() > columns)
        lines.push_back(line), line.clear();
      line += (line.empty() ? "" : " ") + w;
    }
    lines.push_back(line);
  }
  return lines;
}

}  // namespace

void draw_legend(Image& image, const std::string& legend_text, const std::string& warning,
                 const Palette& palette) {
  const int scale = std::max(1, std::min(image.width, image.height) / 700);
  const int margin = 4 * scale, cell_w = kCellWidth * scale, cell_h = kCellHeight * scale;
  const int columns = (image.width - 4 * margin) / cell_w;
  if (columns < 8 || image.height < cell_h + 4 * margin) return;
  std::vector<std::pair<std::string, Rgb>> lines;
  for (const std::string& l : wrap(legend_text, std::size_t(columns)))
    lines.push_back({l, Rgb{20, 20, 20}});
  if (!warning.empty())
    for (const std::string& l : wrap("warning: " + warning, std::size_t(columns)))
      lines.push_back({l, palette.uncovered});
  const int rows = std::min<int>(int(lines.size()), (image.height - 4 * margin) / cell_h);
  std::size_t longest = 0;
  for (int i = 0; i < rows; ++i) longest = std::max(longest, lines[i].first.size());
  // The box: the pixels under it lightened three quarters towards white.
  const int x0 = margin, y1 = image.height - margin;
  const int x1 = x0 + 2 * margin + int(longest) * cell_w, y0 = y1 - 2 * margin - rows * cell_h;
  for (int y = std::max(0, y0); y < y1; ++y)
    for (int x = x0; x < std::min(x1, image.width); ++x)
      for (int k = 0; k < 3; ++k) {
        std::uint8_t& c = image.rgb[3 * (std::size_t(y) * image.width + x) + k];
        c = static_cast<std::uint8_t>(c + (255 - c) * 3 / 4);
      }
  for (int i = 0; i < rows; ++i)
    draw_text(image, x0 + margin, y0 + margin + i * cell_h, lines[i].first, lines[i].second, scale);
}

}  // namespace medspheres::render
