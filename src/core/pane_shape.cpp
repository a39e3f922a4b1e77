#include "reflectance_field_map/core/pane_shape.h"

#include <algorithm>
#include <cmath>

namespace rfm {

bool PaneShape::lineUp(size_t count) const {
  // The principal line through the centroid, then the members' spread across and along it.
  double mean_x = 0.0, mean_y = 0.0;
  for (size_t m = 0; m < count; ++m) {
    mean_x += members_[2 * m];
    mean_y += members_[2 * m + 1];
  }
  mean_x /= static_cast<double>(count);
  mean_y /= static_cast<double>(count);
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

OffPaneCells drawStaticOffPane(const CellBox& box, std::vector<CellClass>& classes,
                               PaneShape& panes) {
  auto class_at = [&](const CellIndex& cell) {
    return box.contains(cell) ? classes[static_cast<size_t>(cell.y() - box.min.y()) * box.width() +
                                        (cell.x() - box.min.x())]
                              : CellClass::kUnknown;
  };
  OffPaneCells drawn;
  for (int i = 0; i < static_cast<int>(classes.size()); ++i) {
    if (!isGlassOrMetal(classes[i])) continue;
    const CellIndex cell(box.min.x() + i % box.width(), box.min.y() + i / box.width());
    if (panes.onPane(cell, class_at)) continue;
    ++(classes[i] == CellClass::kGlass ? drawn.glass : drawn.metal);
    classes[i] = CellClass::kStatic;
    drawn.cells.push_back(i);
  }
  return drawn;
}

}  // namespace rfm
