#pragma once
/// \file
/// A 5 x 8 pixel bitmap font of the printable ASCII characters (32 .. 126), drawn into an
/// Image: text for the legend without a font file or a font library. A glyph cell is 6 x
/// 9 pixels (one column and one row of spacing) at scale 1; any other byte is drawn as '?'.

#include <string>

#include "medspheres/render/render.h"

namespace medspheres::render {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 8;
inline constexpr int kCellWidth = kGlyphWidth + 1, kCellHeight = kGlyphHeight + 1;

/// Draws \p text with its first cell's top left corner at pixel (x, y), each font pixel a
/// \p scale x \p scale square; pixels outside the image are skipped. '\n' starts a new
/// line. \throws std::invalid_argument for scale < 1.
void draw_text(Image& image, int x, int y, const std::string& text, const Rgb& color,
               int scale = 1);

}  // namespace medspheres::render
