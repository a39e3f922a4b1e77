#include "reflectance_field_map/core/pane_shape.h"

#include "reflectance_field_map/core/line_fit.h"

#include <algorithm>
#include <cmath>

namespace rfm {

bool PaneShape::lineUp() const {
  const LineFit line = fitLine(members_);
  return line.across <= kMaxHalfThickness && line.last - line.first + 1.0 >= kMinLength;
}

namespace {

// For every glass or metal cell of `classes`, whether its 8-connected group of glass and metal
// cells holds at least `min_cells` cells; judged on the classes as given.
std::vector<uint8_t> inLargeGroups(const CellBox& box, const std::vector<CellClass>& classes,
                                   int min_cells) {
  const int width = box.width(), height = box.height();
  std::vector<uint8_t> large(classes.size(), 0), seen(classes.size(), 0);
  std::vector<int> group, stack;
  for (int start = 0; start < static_cast<int>(classes.size()); ++start) {
    if (seen[start] || !isGlassOrMetal(classes[start])) continue;
    group.clear();
    stack.assign(1, start);
    seen[start] = 1;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      group.push_back(i);
      const int x = i % width, y = i / width;
      for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, height - 1); ++ny) {
        for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, width - 1); ++nx) {
          const int n = ny * width + nx;
          if (seen[n] || !isGlassOrMetal(classes[n])) continue;
          seen[n] = 1;
          stack.push_back(n);
        }
      }
    }
    if (static_cast<int>(group.size()) < min_cells) continue;
    for (const int i : group)
      large[i] = 1;
  }
  return large;
}

}  // namespace

OffPaneCells drawStaticOffPane(const CellBox& box, std::vector<CellClass>& classes,
                               PaneShape& panes) {
  auto class_at = [&](const CellIndex& cell) { return classInBox(box, classes, cell); };
  const std::vector<uint8_t> large = inLargeGroups(box, classes, PaneShape::kMinGlassCells);
  OffPaneCells drawn;
  for (int i = 0; i < static_cast<int>(classes.size()); ++i) {
    if (!isGlassOrMetal(classes[i])) continue;
    if (large[i] && panes.onPane(box.cellAt(i), class_at)) continue;
    ++(classes[i] == CellClass::kGlass ? drawn.glass : drawn.metal);
    classes[i] = CellClass::kStatic;
    drawn.cells.push_back(i);
  }
  return drawn;
}

}  // namespace rfm
