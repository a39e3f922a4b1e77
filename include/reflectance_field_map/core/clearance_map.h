#pragma once

#include "reflectance_field_map/core/grid_geometry.h"

#include <cstdint>
#include <vector>

namespace rfm {

// How far from any cell of a box the nearest non-empty cell is, as a lower bound kept per block
// of blockCells() x blockCells() cells: at(cell) = d means every cell within Chebyshev distance
// d - 1 of `cell` is empty (0 on or next to non-empty cells). A walk along a ray may leap d - 1
// cells from any point of a cell with clearance d without passing a non-empty cell. Larger
// blocks make the map cheaper to rebuild whenever the classes change; smaller ones let walks
// leap closer to non-empty cells. Cells outside the box have clearance 0.
class ClearanceMap {
 public:
  static constexpr int kMaxBlockShift = 4;
  // Blocks of 2^block_shift cells a side, block_shift in [0, kMaxBlockShift].
  explicit ClearanceMap(int block_shift = 2);
  int blockCells() const { return 1 << shift_; }

  // is_empty(dx, dy): whether cell box.min + (dx, dy) is empty.
  template <typename IsEmpty>
  void compute(const CellBox& box, IsEmpty&& is_empty) {
    box_ = box;
    blocks_x_ = (box.width() + blockCells() - 1) >> shift_;
    const int blocks_y = (box.height() + blockCells() - 1) >> shift_;
    blocks_.assign(static_cast<size_t>(blocks_x_) * blocks_y, kFar);
    for (int dy = 0; dy < box.height(); ++dy) {
      uint8_t* block_row = &blocks_[static_cast<size_t>(dy >> shift_) * blocks_x_];
      for (int dx = 0; dx < box.width(); ++dx) {
        if (!is_empty(dx, dy)) block_row[dx >> shift_] = 0;
      }
    }
    transform();
  }

  int at(const CellIndex& cell) const {
    // Unsigned offsets: one compare per axis tests both sides of the box, and divisions shift.
    const unsigned dx = static_cast<unsigned>(cell.x() - box_.min.x());
    const unsigned dy = static_cast<unsigned>(cell.y() - box_.min.y());
    if (dx >= static_cast<unsigned>(box_.width()) || dy >= static_cast<unsigned>(box_.height())) {
      return 0;
    }
    const int blocks = blocks_[static_cast<size_t>(dy >> shift_) * blocks_x_ + (dx >> shift_)];
    // All blocks within blocks - 1 are empty: so is every cell within blockCells() * (blocks - 1).
    return blocks == 0 ? 0 : ((blocks - 1) << shift_) + 1;
  }

  const CellBox& box() const { return box_; }
  void clear() {
    box_ = CellBox();
    blocks_.clear();
  }

 private:
  static constexpr uint8_t kFar = 255;
  // Block distances from the seeds (0 on blocks holding a non-empty cell, kFar elsewhere).
  void transform();

  int shift_;
  CellBox box_;
  int blocks_x_ = 0;
  std::vector<uint8_t> blocks_;  // per block: Chebyshev distance in blocks to a non-empty one
};

}  // namespace rfm
