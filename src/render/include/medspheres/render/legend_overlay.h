#pragma once
/// \file
/// The legend drawn into a rendered image: its text (legend()) and a warning, in the
/// bitmap font, on a light box at the bottom left, lines wrapped at spaces to the width.

#include <string>

#include "medspheres/render/render.h"

namespace medspheres::render {

/// Draws \p legend_text (lines separated by '\n') and, when not empty, "warning: " +
/// \p warning (in the palette's uncovered colour) into \p image. The font scale grows
/// with the image (1 below 1400 pixels on the shorter side). An image too small for one
/// line is left as it is.
void draw_legend(Image& image, const std::string& legend_text, const std::string& warning,
                 const Palette& palette);

}  // namespace medspheres::render
