#include "reflectance_field_map/core/pane_shape.h"

#include "reflectance_field_map/core/line_fit.h"

#include <algorithm>
#include <cmath>

namespace rfm {

std::optional<Eigen::Vector2d> PaneShape::lineUp() const {
  const LineFit line = fitLine(members_);
  if (line.across > kMaxHalfThickness || line.last - line.first + 1.0 < kMinLength) {
    return std::nullopt;
  }
  return line.direction;
}

bool PaneShape::inPaneSizedGroup(const CellBox& box, const std::vector<CellClass>& classes,
                                 int index) {
  if (const auto known = group_of_.find(index); known != group_of_.end()) {
    return known->second == kPaneSizedGroup;
  }
  group_of_.emplace(index, kSmallGroup);
  collect8Connected(
      box.width(), box.height(), index,
      [&](int n) { return isGlassOrMetal(classes[n]) && group_of_.emplace(n, kSmallGroup).second; },
      stack_, group_);
  if (group_.size() < static_cast<size_t>(kMinGlassCells)) return false;
  for (const int i : group_)
    group_of_[i] = kPaneSizedGroup;
  return true;
}

void PaneShape::forgetGroups() {
  group_of_.clear();
}

OffPaneCells drawStaticOffPane(const CellBox& box, std::vector<CellClass>& classes,
                               PaneShape& panes, const FacesNormal& faces_normal) {
  auto class_at = [&](const CellIndex& cell) { return classInBox(box, classes, cell); };
  OffPaneCells drawn;
  // A group is measured when its first cell (in index order) is reached, before any of its cells
  // is redrawn: cells redrawn earlier belong to other groups.
  for (int i = 0; i < static_cast<int>(classes.size()); ++i) {
    if (!isGlassOrMetal(classes[i])) continue;
    if (panes.inPaneSizedGroup(box, classes, i)) {
      const std::optional<Eigen::Vector2d> along = panes.paneDirection(box.cellAt(i), class_at);
      if (along && (!faces_normal || faces_normal(i, Eigen::Vector2d(-along->y(), along->x()),
                                                  PaneShape::kMaxLobeOffNormal))) {
        continue;
      }
    }
    ++(classes[i] == CellClass::kGlass ? drawn.glass : drawn.metal);
    classes[i] = CellClass::kStatic;
    drawn.cells.push_back(i);
  }
  panes.forgetGroups();
  return drawn;
}

}  // namespace rfm
