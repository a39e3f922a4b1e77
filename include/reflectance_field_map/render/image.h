#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfm {
namespace render {

// 8-bit RGB colour.
struct Rgb {
  uint8_t r = 0;
  uint8_t g = 0;
  uint8_t b = 0;
  bool operator==(const Rgb& other) const { return r == other.r && g == other.g && b == other.b; }
  bool operator!=(const Rgb& other) const { return !(*this == other); }
};

// A row-major RGB picture, row 0 at the top (as written to PNG).
class RgbImage {
 public:
  RgbImage() = default;
  RgbImage(int width, int height, Rgb fill = {});

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return width_ == 0 || height_ == 0; }

  Rgb at(int x, int y) const {
    const uint8_t* p = &pixels_[index(x, y)];
    return {p[0], p[1], p[2]};
  }
  void set(int x, int y, Rgb c) {
    uint8_t* p = &pixels_[index(x, y)];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  }
  // Fills the rectangle [x, x + w) x [y, y + h), clipped to the picture.
  void fillRect(int x, int y, int w, int h, Rgb c);

  // Nearest-neighbour enlargement by integer factors (>= 1).
  RgbImage scaled(int factor_x, int factor_y) const;

  // width * height * 3 bytes, R G B per pixel, rows top to bottom.
  const std::vector<uint8_t>& pixels() const { return pixels_; }
  uint8_t* data() { return pixels_.data(); }

 private:
  size_t index(int x, int y) const {
    return (static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)) * 3;
  }

  int width_ = 0;
  int height_ = 0;
  std::vector<uint8_t> pixels_;
};

}  // namespace render
}  // namespace rfm
