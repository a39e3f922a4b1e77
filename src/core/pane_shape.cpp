#include "reflectance_field_map/core/pane_shape.h"

#include "reflectance_field_map/core/line_fit.h"

#include <algorithm>
#include <cmath>

namespace rfm {

bool PaneShape::lineUp() const {
  const LineFit line = fitLine(members_);
  return line.across <= kMaxHalfThickness && line.last - line.first + 1.0 >= kMinLength;
}

OffPaneCells drawStaticOffPane(const CellBox& box, std::vector<CellClass>& classes,
                               PaneShape& panes) {
  auto class_at = [&](const CellIndex& cell) { return classInBox(box, classes, cell); };
  OffPaneCells drawn;
  for (int i = 0; i < static_cast<int>(classes.size()); ++i) {
    if (!isGlassOrMetal(classes[i])) continue;
    if (panes.onPane(box.cellAt(i), class_at)) continue;
    ++(classes[i] == CellClass::kGlass ? drawn.glass : drawn.metal);
    classes[i] = CellClass::kStatic;
    drawn.cells.push_back(i);
  }
  return drawn;
}

}  // namespace rfm
