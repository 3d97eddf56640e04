#include "medspheres/render/png_write.h"

#include <csetjmp>
#include <stdexcept>

#include <png.h>

#include "medspheres/error.h"
#include "medspheres/io.h"

namespace medspheres::render {

namespace {

void append_bytes(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  out->append(reinterpret_cast<const char*>(data), length);
}

void no_flush(png_structp) {}

// libpng reports errors by longjmp; everything it touches lives in encode_png's frame
// and is released there, so nothing with a destructor is skipped by the jump.
bool encode(const Image& image, std::vector<png_text>& chunks, std::vector<png_bytep>& rows,
            std::string& out) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &out, append_bytes, no_flush);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!chunks.empty()) png_set_text(png, info, chunks.data(), static_cast<int>(chunks.size()));
  png_set_rows(png, info, rows.data());
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

std::string encode_png(const Image& image, const PngText& text) {
  if (image.width < 1 || image.height < 1 ||
      image.rgb.size() != std::size_t(3) * image.width * image.height)
    throw std::invalid_argument("encode_png: empty image or wrong pixel count");
  for (const auto& [key, value] : text)
    if (key.empty() || key.size() > 79)
      throw std::invalid_argument("encode_png: a PNG text keyword has 1 to 79 characters");
  std::vector<png_text> chunks(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    chunks[i].compression = PNG_TEXT_COMPRESSION_NONE;
    chunks[i].key = const_cast<char*>(text[i].first.c_str());
    chunks[i].text = const_cast<char*>(text[i].second.c_str());
  }
  std::vector<png_bytep> rows(image.height);
  for (int y = 0; y < image.height; ++y)
    rows[y] = const_cast<png_bytep>(&image.rgb[std::size_t(3) * image.width * y]);
  std::string out;
  if (!encode(image, chunks, rows, out)) throw Error("libpng failed to encode the image");
  return out;
}

void write_png(const std::string& path, const Image& image, const PngText& text) {
  write_file_atomically(path, encode_png(image, text));
}

}  // namespace medspheres::render
