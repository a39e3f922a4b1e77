#include "reflectance_field_map/tools/comparison_picture.h"

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/render/map_image.h"
#include "reflectance_field_map/render/png_io.h"
#include "reflectance_field_map/tools/map_comparison.h"

#include <algorithm>
#include <filesystem>

namespace rfm::tools {
namespace {

constexpr int kPanelGap = 4;
const render::Rgb kGapColor{255, 255, 255};

CellClass cellClassOf(uint8_t code) {
  switch (code) {
    case kCodeFree:
      return CellClass::kFree;
    case kCodeStatic:
      return CellClass::kStatic;
    case kCodeGlass:
      return CellClass::kGlass;
    case kCodeMetal:
      return CellClass::kMetal;
    case kCodeMotion:
      return CellClass::kMotion;
    default:
      return CellClass::kUnknown;
  }
}

// Higher wins a block of the RFM's panel.
int rfmPriority(uint8_t code) {
  switch (code) {
    case kCodeGlass:
    case kCodeMetal:
      return 5;
    case kCodeStatic:
      return 4;
    case kCodeMotion:
      return 3;
    case kCodeFree:
      return 2;
    default:
      return 1;
  }
}

struct PlainCell {
  int priority = 0;
  render::Rgb color;
};

// The union of both maps, in the plain grid's cells.
struct UnionBox {
  int min_x, min_y, max_x, max_y;
};

}  // namespace

render::Rgb plainOccupiedColor() {
  return {0, 0, 0};
}

render::Rgb droppedColor(uint8_t code) {
  switch (code) {
    case kCodeMotion:
      return render::classColor(CellClass::kMotion);
    case kCodeFree:
      return {255, 140, 0};  // orange
    default:
      return {0, 190, 210};  // unknown: teal
  }
}

render::RgbImage renderComparison(const GridMap& rfm, const GridMap& plain, int cells_per_pixel) {
  const CellOffset plain_to_rfm = alignment(plain, rfm);
  const UnionBox box{std::min(0, -plain_to_rfm.dx), std::min(0, -plain_to_rfm.dy),
                     std::max(plain.width, rfm.width - plain_to_rfm.dx),
                     std::max(plain.height, rfm.height - plain_to_rfm.dy)};
  const int k = std::max(1, cells_per_pixel);
  const int panel_w = (box.max_x - box.min_x + k - 1) / k;
  const int panel_h = (box.max_y - box.min_y + k - 1) / k;
  render::RgbImage image(2 * panel_w + kPanelGap, panel_h, kGapColor);
  for (int py = 0; py < panel_h; ++py) {
    for (int px = 0; px < panel_w; ++px) {
      uint8_t best_code = kCodeUnknown;
      PlainCell best_plain{0, render::classColor(CellClass::kUnknown)};
      // Block of cells, y up: picture row 0 holds the highest cells.
      const int y_top = box.max_y - py * k;
      for (int y = std::max(box.min_y, y_top - k); y < y_top; ++y) {
        for (int x = box.min_x + px * k; x < std::min(box.max_x, box.min_x + (px + 1) * k); ++x) {
          const int rx = x + plain_to_rfm.dx, ry = y + plain_to_rfm.dy;
          const uint8_t code = classAt(rfm, rx, ry);
          if (rfmPriority(code) > rfmPriority(best_code)) best_code = code;
          if (!plain.contains(x, y)) continue;
          PlainCell cell;
          switch (plain.occupancyAt(x, y)) {
            case Occupancy::kOccupied:
              if (occupiedWithin(rfm, rx, ry, 1)) {
                cell = {3, plainOccupiedColor()};
              } else {
                cell = {4, droppedColor(code)};
              }
              break;
            case Occupancy::kFree:
              cell = {2, render::classColor(CellClass::kFree)};
              break;
            case Occupancy::kUnknown:
              cell = {1, render::classColor(CellClass::kUnknown)};
              break;
          }
          if (cell.priority > best_plain.priority) best_plain = cell;
        }
      }
      image.set(px, py, render::classColor(cellClassOf(best_code)));
      image.set(panel_w + kPanelGap + px, py, best_plain.color);
    }
  }
  return image;
}

int writeComparisonPicture(const std::string& path, const GridMap& rfm, const GridMap& plain,
                           int max_width, std::size_t max_bytes) {
  const CellOffset plain_to_rfm = alignment(plain, rfm);
  const int union_width =
      std::max(plain.width, rfm.width - plain_to_rfm.dx) - std::min(0, -plain_to_rfm.dx);
  // Two panels and the gap within max_width.
  int k = 1;
  while (2 * ((union_width + k - 1) / k) + kPanelGap > max_width)
    ++k;
  for (;; ++k) {
    render::writePng(path, renderComparison(rfm, plain, k));
    if (std::filesystem::file_size(path) <= max_bytes || k > union_width) return k;
  }
}

render::Rgb transientColor() {
  return {230, 0, 0};
}

render::RgbImage renderPeopleLeft(const std::vector<GridMap>& maps,
                                  const TransientEvidence& evidence, int scale) {
  if (maps.empty()) return {};
  int min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  std::vector<std::pair<int, int>> origins;
  for (std::size_t m = 0; m < maps.size(); ++m) {
    int ox = 0, oy = 0;
    mapCellOrigin(maps[m], ox, oy);
    origins.emplace_back(ox, oy);
    min_x = m == 0 ? ox : std::min(min_x, ox);
    min_y = m == 0 ? oy : std::min(min_y, oy);
    max_x = m == 0 ? ox + maps[m].width : std::max(max_x, ox + maps[m].width);
    max_y = m == 0 ? oy + maps[m].height : std::max(max_y, oy + maps[m].height);
  }
  const int panel_w = max_x - min_x, panel_h = max_y - min_y;
  const int panels = static_cast<int>(maps.size());
  render::RgbImage image(panels * panel_w + (panels - 1) * kPanelGap, panel_h, kGapColor);
  for (int m = 0; m < panels; ++m) {
    const GridMap& map = maps[static_cast<std::size_t>(m)];
    const auto [ox, oy] = origins[static_cast<std::size_t>(m)];
    const int left = m * (panel_w + kPanelGap);
    for (int y = min_y; y < max_y; ++y) {
      for (int x = min_x; x < max_x; ++x) {
        const int mx = x - ox, my = y - oy;
        render::Rgb color = render::classColor(CellClass::kUnknown);
        if (map.contains(mx, my)) {
          switch (map.occupancyAt(mx, my)) {
            case Occupancy::kOccupied:
              color = evidence.isTransient(x, y) ? transientColor() : plainOccupiedColor();
              break;
            case Occupancy::kFree:
              color = render::classColor(CellClass::kFree);
              break;
            case Occupancy::kUnknown:
              break;
          }
        }
        image.set(left + x - min_x, max_y - 1 - y, color);
      }
    }
  }
  return image.scaled(std::max(1, scale), std::max(1, scale));
}

}  // namespace rfm::tools
