#pragma once
/// \file
/// PNG encoding of an Image with libpng: 8-bit RGB, with tEXt chunks (keyword, text).

#include <string>
#include <utility>
#include <vector>

#include "medspheres/render/render.h"

namespace medspheres::render {

using PngText = std::vector<std::pair<std::string, std::string>>;

/// The PNG file's bytes. Keywords must be 1 to 79 Latin-1 characters (PNG's rule).
/// \throws std::invalid_argument for an empty image or a bad keyword; Error when libpng
///   reports a failure.
std::string encode_png(const Image& image, const PngText& text = {});

/// encode_png() written to \p path atomically (write_file_atomically: on failure nothing
/// is left at \p path). Throws as both.
void write_png(const std::string& path, const Image& image, const PngText& text = {});

}  // namespace medspheres::render
