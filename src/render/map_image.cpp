#include "reflectance_field_map/render/map_image.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace rfm {
namespace render {

Rgb classColor(CellClass c) {
  switch (c) {
    case CellClass::kUnknown:
      return {160, 160, 160};
    case CellClass::kFree:
      return {245, 245, 245};
    case CellClass::kStatic:
      return {0, 110, 40};
    case CellClass::kGlass:
      return {20, 90, 255};
    case CellClass::kMetal:
      return {225, 20, 20};
    case CellClass::kMotion:
      return {235, 0, 235};
    case CellClass::kOccupied:
      return {0, 0, 0};
  }
  return {255, 255, 0};  // not a class: stands out
}

RgbImage renderMap(const GlobalMap2D& map, const CellBox& box, int scale) {
  if (scale < 1) throw std::invalid_argument("renderMap: scale must be >= 1");
  if (box.empty()) return {};
  std::vector<CellClass> cells;
  map.extract(box, cells);
  const int w = box.width(), h = box.height();
  RgbImage image(w, h);
  for (int y = 0; y < h; ++y) {
    const int row = h - 1 - y;  // y up: the highest cell row is the top picture row
    for (int x = 0; x < w; ++x) {
      image.set(
          x, row,
          classColor(
              cells[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)]));
    }
  }
  return image.scaled(scale, scale);
}

RgbImage renderMap(const GlobalMap2D& map, int scale) {
  return renderMap(map, map.bounds(), scale);
}

int autoScale(const CellBox& box, int target_pixels, int max_scale) {
  const int longer = std::max(box.width(), box.height());
  if (longer <= 0) return 1;
  return std::clamp(target_pixels / longer, 1, std::max(1, max_scale));
}

}  // namespace render
}  // namespace rfm
