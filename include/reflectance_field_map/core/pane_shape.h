// Which glass and metal cells Alg. 3 cuts rays at: those that lie on a pane.
#pragma once

#include "reflectance_field_map/core/cell_class.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rfm {

// Alg. 3 distrusts what a ray saw beyond glass because a pane let it through. A pane is thin and
// straight: in the scan's plane, a line of obstacle cells (its glass, its frames, the wall it is
// set in). Glass or metal cells on no such line (returns from clutter, from something seen from
// one place only, from the rough face of a thick wall) give no reason to distrust a ray that
// passed them; the reflection check reads them as static, which lets through a ray in any
// direction they were seen narrowly from.
//
// A cell lies on a pane when the obstacle cells 8-connected to it within kWindowRadius cells lie
// within kMaxHalfThickness cells of their principal line and span at least kMinLength cells
// along it.
class PaneShape {
 public:
  static constexpr int kWindowRadius = 4;
  static constexpr double kMinLength = 5.0;
  static constexpr double kMaxHalfThickness = 2.5;

  // Glass and metal cells of `classes` (row-major, `width` cells a row) that lie on no pane become
  // static. Other cells are never changed, so the result does not depend on the order of cells.
  // Returns the number of cells changed.
  size_t demoteOffPane(int width, std::vector<CellClass>& classes);

  // Whether the glass or metal cell (x, y) of `classes` lies on a pane.
  bool onPane(int width, const std::vector<CellClass>& classes, int x, int y);

 private:
  static constexpr int kSide = 2 * kWindowRadius + 1;
  std::array<uint8_t, kSide * kSide> seen_{};
  std::array<int16_t, 2 * kSide * kSide> members_{};  // (dx, dy) pairs from the cell
  std::vector<int> stack_;
};

}  // namespace rfm
