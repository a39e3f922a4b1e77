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
  // along the row. Minima in any order are the same distances as relaxing block by block.
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
  // Along a row from `first` in steps of `step`: each block's distance is its own or one more
  // than the block before. Four blocks at a time: their distances among themselves do not wait
  // for the run before them, so the chain from block to block is one add and one minimum for
  // every four.
  auto along_row = [](uint8_t* first, int step, int count) {
    int run = first[0];
    int i = 1;
    for (; i + 4 <= count; i += 4) {
      uint8_t* b = first + i * step;
      const int d0 = b[0];
      const int d1 = std::min<int>(b[step], d0 + 1);
      const int d2 = std::min<int>(b[2 * step], d1 + 1);
      const int d3 = std::min<int>(b[3 * step], d2 + 1);
      b[0] = static_cast<uint8_t>(std::min(d0, run + 1));
      b[step] = static_cast<uint8_t>(std::min(d1, run + 2));
      b[2 * step] = static_cast<uint8_t>(std::min(d2, run + 3));
      run = std::min(d3, run + 4);
      b[3 * step] = static_cast<uint8_t>(run);
    }
    for (; i < count; ++i) {
      uint8_t& d = first[i * step];
      run = std::min<int>(d, run + 1);
      d = static_cast<uint8_t>(run);
    }
  };
  uint8_t* const c = blocks_.data();
  for (int y = 0; y < h; ++y) {
    uint8_t* row = c + static_cast<size_t>(y) * w;
    if (y > 0) from_row(row, row - w);
    along_row(row, 1, w);
  }
  for (int y = h - 1; y >= 0; --y) {
    uint8_t* row = c + static_cast<size_t>(y) * w;
    if (y + 1 < h) from_row(row, row + w);
    along_row(row + w - 1, -1, w);
  }
}

}  // namespace rfm
