#include "reflectance_field_map/core/clearance_map.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rfm {

ClearanceMap::ClearanceMap(int block_shift) : shift_(block_shift) {
  if (block_shift < 0 || block_shift > kMaxBlockShift) {
    throw std::invalid_argument("block_shift not in [0, " + std::to_string(kMaxBlockShift) + "]");
  }
}

void ClearanceMap::transform() {
  const int h = static_cast<int>(blocks_.size()) / std::max(blocks_x_, 1);
  // Two-pass chamfer with unit weights on all eight neighbours: the Chebyshev distance. Blocks
  // beyond the box count as empty: rays are clipped to the box.
  const int w = blocks_x_;
  uint8_t* c = blocks_.data();
  auto relax = [](uint8_t& cell, int neighbour) {
    if (neighbour + 1 < cell) cell = static_cast<uint8_t>(neighbour + 1);
  };
  for (int y = 0; y < h; ++y) {
    uint8_t* row = c + static_cast<size_t>(y) * w;
    const uint8_t* above = y > 0 ? row - w : nullptr;
    for (int x = 0; x < w; ++x) {
      if (x > 0) relax(row[x], row[x - 1]);
      if (above) {
        relax(row[x], above[x]);
        if (x > 0) relax(row[x], above[x - 1]);
        if (x + 1 < w) relax(row[x], above[x + 1]);
      }
    }
  }
  for (int y = h - 1; y >= 0; --y) {
    uint8_t* row = c + static_cast<size_t>(y) * w;
    const uint8_t* below = y + 1 < h ? row + w : nullptr;
    for (int x = w - 1; x >= 0; --x) {
      if (x + 1 < w) relax(row[x], row[x + 1]);
      if (below) {
        relax(row[x], below[x]);
        if (x > 0) relax(row[x], below[x - 1]);
        if (x + 1 < w) relax(row[x], below[x + 1]);
      }
    }
  }
}

}  // namespace rfm
