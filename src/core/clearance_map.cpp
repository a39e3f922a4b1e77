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
  const int w = blocks_x_;
  // Two-pass chamfer with unit weights on all eight neighbours: the Chebyshev distance. Blocks
  // beyond the box count as empty: rays are clipped to the box. Each pass takes a row's three
  // neighbours in the row before at once (no dependency along the row: vectorised), then runs
  // along the row with the distance so far in a register. Minima in any order are the same
  // distances as relaxing block by block: single-cell blocks in a third of the time.
  auto one_more = [](uint8_t d) { return static_cast<uint8_t>(d + (d != kFar)); };
  auto from_row = [w, one_more](uint8_t* row, const uint8_t* previous) {
    if (w == 1) {
      row[0] = std::min(row[0], one_more(previous[0]));
      return;
    }
    row[0] = std::min(row[0], one_more(std::min(previous[0], previous[1])));
    for (int x = 1; x + 1 < w; ++x) {
      const uint8_t nearest = std::min(std::min(previous[x - 1], previous[x]), previous[x + 1]);
      row[x] = std::min(row[x], one_more(nearest));
    }
    row[w - 1] = std::min(row[w - 1], one_more(std::min(previous[w - 2], previous[w - 1])));
  };
  uint8_t* const c = blocks_.data();
  for (int y = 0; y < h; ++y) {
    uint8_t* row = c + static_cast<size_t>(y) * w;
    if (y > 0) from_row(row, row - w);
    int run = row[0];
    for (int x = 1; x < w; ++x)
      row[x] = static_cast<uint8_t>(run = std::min<int>(row[x], run + 1));
  }
  for (int y = h - 1; y >= 0; --y) {
    uint8_t* row = c + static_cast<size_t>(y) * w;
    if (y + 1 < h) from_row(row, row + w);
    int run = row[w - 1];
    for (int x = w - 2; x >= 0; --x)
      row[x] = static_cast<uint8_t>(run = std::min<int>(row[x], run + 1));
  }
}

}  // namespace rfm
