#include "reflectance_field_map/core/pane_shape.h"

#include <algorithm>
#include <cmath>

namespace rfm {

size_t PaneShape::demoteOffPane(int width, std::vector<CellClass>& classes) {
  // Demoting keeps a cell an obstacle, so later cells see the same neighbourhoods.
  size_t demoted = 0;
  for (size_t i = 0; i < classes.size(); ++i) {
    if (classes[i] != CellClass::kGlass && classes[i] != CellClass::kMetal) continue;
    const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
    if (!onPane(width, classes, x, y)) {
      classes[i] = CellClass::kStatic;
      ++demoted;
    }
  }
  return demoted;
}

bool PaneShape::onPane(int width, const std::vector<CellClass>& classes, int x, int y) {
  const int height = static_cast<int>(classes.size() / width);
  auto obstacle = [](CellClass c) {
    return c == CellClass::kStatic || c == CellClass::kGlass || c == CellClass::kMetal;
  };
  // The obstacle cells connected to (x, y) inside the window, as offsets from it.
  seen_.fill(0);
  size_t count = 0;
  auto local = [](int dx, int dy) { return (dy + kWindowRadius) * kSide + dx + kWindowRadius; };
  stack_.assign(1, local(0, 0));
  seen_[local(0, 0)] = 1;
  double sum_x = 0.0, sum_y = 0.0;
  while (!stack_.empty()) {
    const int l = stack_.back();
    stack_.pop_back();
    const int dx = l % kSide - kWindowRadius, dy = l / kSide - kWindowRadius;
    members_[2 * count] = static_cast<int16_t>(dx);
    members_[2 * count + 1] = static_cast<int16_t>(dy);
    ++count;
    sum_x += dx;
    sum_y += dy;
    for (int ny = std::max(dy - 1, -kWindowRadius); ny <= std::min(dy + 1, kWindowRadius); ++ny) {
      for (int nx = std::max(dx - 1, -kWindowRadius); nx <= std::min(dx + 1, kWindowRadius); ++nx) {
        const int cx = x + nx, cy = y + ny;
        if (cx < 0 || cy < 0 || cx >= width || cy >= height || seen_[local(nx, ny)]) continue;
        seen_[local(nx, ny)] = 1;
        if (obstacle(classes[static_cast<size_t>(cy) * width + cx]))
          stack_.push_back(local(nx, ny));
      }
    }
  }
  // Principal line through the centroid, then the members' spread across and along it.
  const double mean_x = sum_x / count, mean_y = sum_y / count;
  double xx = 0.0, xy = 0.0, yy = 0.0;
  for (size_t m = 0; m < count; ++m) {
    const double px = members_[2 * m] - mean_x, py = members_[2 * m + 1] - mean_y;
    xx += px * px;
    xy += px * py;
    yy += py * py;
  }
  const double angle = 0.5 * std::atan2(2.0 * xy, xx - yy);
  const double ux = std::cos(angle), uy = std::sin(angle);
  double across = 0.0, first = 0.0, last = 0.0;
  for (size_t m = 0; m < count; ++m) {
    const double px = members_[2 * m] - mean_x, py = members_[2 * m + 1] - mean_y;
    across = std::max(across, std::abs(px * uy - py * ux));
    const double along = px * ux + py * uy;
    first = std::min(first, along);
    last = std::max(last, along);
  }
  return across <= kMaxHalfThickness && last - first + 1.0 >= kMinLength;
}

}  // namespace rfm
