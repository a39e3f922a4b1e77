#include "reflectance_field_map/render/image.h"

#include <algorithm>

namespace rfm {
namespace render {

RgbImage::RgbImage(int width, int height, Rgb fill) {
  if (width < 0 || height < 0) throw std::invalid_argument("RgbImage: negative size");
  width_ = width;
  height_ = height;
  pixels_.resize(static_cast<size_t>(width) * static_cast<size_t>(height) * 3);
  for (size_t i = 0; i < pixels_.size(); i += 3) {
    pixels_[i] = fill.r;
    pixels_[i + 1] = fill.g;
    pixels_[i + 2] = fill.b;
  }
}

void RgbImage::fillRect(int x, int y, int w, int h, Rgb c) {
  const int x0 = std::max(x, 0), y0 = std::max(y, 0);
  const int x1 = std::min(x + w, width_), y1 = std::min(y + h, height_);
  for (int yy = y0; yy < y1; ++yy) {
    for (int xx = x0; xx < x1; ++xx)
      set(xx, yy, c);
  }
}

RgbImage RgbImage::scaled(int factor_x, int factor_y) const {
  if (factor_x < 1 || factor_y < 1) throw std::invalid_argument("RgbImage: scale factor < 1");
  if (factor_x == 1 && factor_y == 1) return *this;
  RgbImage out(width_ * factor_x, height_ * factor_y);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x)
      out.fillRect(x * factor_x, y * factor_y, factor_x, factor_y, at(x, y));
  }
  return out;
}

}  // namespace render
}  // namespace rfm
