#pragma once

#include "reflectance_field_map/core/grid_geometry.h"

#include <cstdint>
#include <vector>

namespace rfm {

// How far from any cell of a box the nearest non-empty cell is, as a lower bound kept per block
// of kBlock x kBlock cells: at(cell) = d means every cell within Chebyshev distance d - 1 of
// `cell` is empty (0 on or next to non-empty cells). A walk along a ray may leap d - 1 cells
// from any point of a cell with clearance d without passing a non-empty cell. Blocks make the
// map cheap to rebuild whenever the classes change; cells outside the box have clearance 0.
class ClearanceMap {
 public:
  static constexpr int kBlock = 4;

  // fill(empty) sets empty[i] = 1 for each empty cell, row-major over `box` (x fastest).
  template <typename FillEmpty>
  void compute(const CellBox& box, FillEmpty&& fill) {
    box_ = box;
    empty_.assign(static_cast<size_t>(box.width()) * box.height(), 0);
    fill(empty_);
    transform();
  }

  int at(const CellIndex& cell) const {
    if (!box_.contains(cell)) return 0;
    const int bx = (cell.x() - box_.min.x()) / kBlock, by = (cell.y() - box_.min.y()) / kBlock;
    const int blocks = blocks_[static_cast<size_t>(by) * blocks_x_ + bx];
    // All blocks within blocks - 1 are empty: so is every cell within kBlock * (blocks - 1).
    return blocks == 0 ? 0 : kBlock * (blocks - 1) + 1;
  }

  const CellBox& box() const { return box_; }
  void clear() {
    box_ = CellBox();
    empty_.clear();
    blocks_.clear();
  }

 private:
  void transform();

  CellBox box_;
  int blocks_x_ = 0;
  std::vector<uint8_t> empty_;   // per cell
  std::vector<uint8_t> blocks_;  // per block: Chebyshev distance in blocks to a non-empty one
};

}  // namespace rfm
