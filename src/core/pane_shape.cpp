#include "reflectance_field_map/core/pane_shape.h"

#include "reflectance_field_map/core/line_fit.h"

#include <algorithm>
#include <cmath>

namespace rfm {

bool PaneShape::lineUp() const {
  const LineFit line = fitLine(members_);
  return line.across <= kMaxHalfThickness && line.last - line.first + 1.0 >= kMinLength;
}

bool PaneShape::inPaneSizedGroup(const CellBox& box, const std::vector<CellClass>& classes,
                                 int index) {
  if (group_of_.size() < classes.size()) group_of_.resize(classes.size(), kUngrouped);
  if (group_of_[index] == kUngrouped) {
    // Flood the 8-connected glass and metal cells from this one; the group's cells follow
    // grouped_'s end.
    const int width = box.width(), height = box.height();
    const size_t first = grouped_.size();
    group_of_[index] = kSmallGroup;
    grouped_.push_back(index);
    for (size_t next = first; next < grouped_.size(); ++next) {
      const int x = grouped_[next] % width, y = grouped_[next] / width;
      for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, height - 1); ++ny) {
        for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, width - 1); ++nx) {
          const int n = ny * width + nx;
          if (group_of_[n] != kUngrouped || !isGlassOrMetal(classes[n])) continue;
          group_of_[n] = kSmallGroup;
          grouped_.push_back(n);
        }
      }
    }
    if (grouped_.size() - first >= static_cast<size_t>(kMinGlassCells)) {
      for (size_t g = first; g < grouped_.size(); ++g)
        group_of_[grouped_[g]] = kPaneSizedGroup;
    }
  }
  return group_of_[index] == kPaneSizedGroup;
}

void PaneShape::forgetGroups() {
  for (const int i : grouped_)
    group_of_[i] = kUngrouped;
  grouped_.clear();
}

OffPaneCells drawStaticOffPane(const CellBox& box, std::vector<CellClass>& classes,
                               PaneShape& panes) {
  auto class_at = [&](const CellIndex& cell) { return classInBox(box, classes, cell); };
  OffPaneCells drawn;
  // A group is measured when its first cell (in index order) is reached, before any of its cells
  // is redrawn: cells redrawn earlier belong to other groups.
  for (int i = 0; i < static_cast<int>(classes.size()); ++i) {
    if (!isGlassOrMetal(classes[i])) continue;
    if (panes.inPaneSizedGroup(box, classes, i) && panes.onPane(box.cellAt(i), class_at)) continue;
    ++(classes[i] == CellClass::kGlass ? drawn.glass : drawn.metal);
    classes[i] = CellClass::kStatic;
    drawn.cells.push_back(i);
  }
  panes.forgetGroups();
  return drawn;
}

}  // namespace rfm
