#include "reflectance_field_map/render/png_io.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace rfm {
namespace render {
namespace {

struct FileCloser {
  void operator()(FILE* file) const {
    if (file) std::fclose(file);
  }
};
using File = std::unique_ptr<FILE, FileCloser>;

// libpng reports errors through a callback; we keep its message and longjmp back.
struct ErrorState {
  char message[256] = "unknown libpng error";
};

void onPngError(png_structp png, png_const_charp message) {
  auto* state = static_cast<ErrorState*>(png_get_error_ptr(png));
  if (state) {
    std::snprintf(state->message, sizeof(state->message), "%s", message);
  }
  png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

}  // namespace

void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
  if (width <= 0 || height <= 0) {
    throw PngError("cannot write " + path + ": empty picture (" + std::to_string(width) + "x" +
                   std::to_string(height) + ")");
  }
  const size_t expected = static_cast<size_t>(width) * static_cast<size_t>(height) * 3;
  if (rgb.size() != expected) {
    throw PngError("cannot write " + path + ": " + std::to_string(rgb.size()) +
                   " bytes given for a " + std::to_string(width) + "x" + std::to_string(height) +
                   " RGB picture (" + std::to_string(expected) + " expected)");
  }
  File file(std::fopen(path.c_str(), "wb"));
  if (!file) throw PngError("cannot write " + path + ": " + std::strerror(errno));

  ErrorState state;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, onPngError, onPngWarning);
  if (!png) throw PngError("cannot write " + path + ": libpng initialisation failed");
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw PngError("cannot write " + path + ": libpng initialisation failed");
  }
  // Row pointers are prepared before setjmp so nothing with a destructor is created after it.
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    rows[static_cast<size_t>(y)] =
        const_cast<png_bytep>(rgb.data() + static_cast<size_t>(y) * static_cast<size_t>(width) * 3);
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw PngError("cannot write " + path + ": " + state.message);
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 6);
  png_write_info(png, info);
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);

  FILE* raw = file.release();
  if (std::fclose(raw) != 0) throw PngError("cannot write " + path + ": " + std::strerror(errno));
}

void writePng(const std::string& path, const RgbImage& image) {
  writePng(path, image.width(), image.height(), image.pixels());
}

RgbImage readPng(const std::string& path) {
  File file(std::fopen(path.c_str(), "rb"));
  if (!file) throw PngError("cannot read " + path + ": " + std::strerror(errno));
  unsigned char signature[8];
  if (std::fread(signature, 1, sizeof(signature), file.get()) != sizeof(signature) ||
      png_sig_cmp(signature, 0, sizeof(signature)) != 0) {
    throw PngError("cannot read " + path + ": not a PNG file");
  }

  ErrorState state;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, onPngError, onPngWarning);
  if (!png) throw PngError("cannot read " + path + ": libpng initialisation failed");
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    throw PngError("cannot read " + path + ": libpng initialisation failed");
  }
  // Phase 1: header. No C++ object is created or changed between setjmp and a possible longjmp.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw PngError("cannot read " + path + ": " + state.message);
  }
  png_init_io(png, file.get());
  png_set_sig_bytes(png, sizeof(signature));
  png_read_info(png, info);
  const png_byte color_type = png_get_color_type(png, info);
  const png_byte bit_depth = png_get_bit_depth(png, info);
  if (bit_depth == 16) png_set_strip_16(png);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (color_type == PNG_COLOR_TYPE_GRAY || color_type == PNG_COLOR_TYPE_GRAY_ALPHA) {
    png_set_gray_to_rgb(png);
  }
  png_set_strip_alpha(png);
  png_read_update_info(png, info);
  const int width = static_cast<int>(png_get_image_width(png, info));
  const int height = static_cast<int>(png_get_image_height(png, info));
  if (png_get_rowbytes(png, info) != static_cast<size_t>(width) * 3) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw PngError("cannot read " + path + ": unsupported pixel layout");
  }

  // Phase 2: pixels, straight into the picture's buffer.
  RgbImage image(width, height);
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    rows[static_cast<size_t>(y)] =
        image.data() + static_cast<size_t>(y) * static_cast<size_t>(width) * 3;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw PngError("cannot read " + path + ": " + state.message);
  }
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return image;
}

}  // namespace render
}  // namespace rfm
