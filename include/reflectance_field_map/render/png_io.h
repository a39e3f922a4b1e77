#pragma once

#include "reflectance_field_map/render/image.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfm {
namespace render {

// Writing or reading a PNG failed; what() names the file and the reason.
class PngError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes an 8-bit RGB PNG. `rgb` holds width * height * 3 bytes, rows top to bottom.
// Throws PngError (naming `path`) when the size is inconsistent or the file can't be written.
void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);
void writePng(const std::string& path, const RgbImage& image);

// Reads any 8-bit or 16-bit PNG (grey, palette, alpha are converted) as RGB. Throws PngError.
RgbImage readPng(const std::string& path);

}  // namespace render
}  // namespace rfm
