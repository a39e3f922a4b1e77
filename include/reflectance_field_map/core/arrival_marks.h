// The cells where the live labels judged an arrival since the classes last changed (labelRays).
#pragma once

#include "reflectance_field_map/core/grid_geometry.h"

#include <cstdint>
#include <unordered_set>

namespace rfm {

// An arrival is judged on the first returns in a cell that the field had seen free. A person
// stays in a cell for several scans (at 40 Hz and 1 m/s they move a quarter of a cell a scan),
// and after two or three of them the bin holds the person's own hits: the field no longer says
// the cell was free. The marks carry the judgement to the returns that follow in the cell or
// beside it, until motion removal judges the object (the mapper clears them when the classes
// change). Only arrivals where the cell was seen free firmly are marked (labelRays).
class ArrivalMarks {
 public:
  void clear() { cells_.clear(); }
  void mark(const CellIndex& cell) { cells_.insert(key(cell.x(), cell.y())); }
  // Whether the cell or one of its 8 neighbours is marked.
  bool nearMarked(const CellIndex& cell) const {
    if (cells_.empty()) return false;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (cells_.count(key(cell.x() + dx, cell.y() + dy)) > 0) return true;
      }
    }
    return false;
  }

 private:
  static uint64_t key(int x, int y) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(x)) << 32) | static_cast<uint32_t>(y);
  }
  std::unordered_set<uint64_t> cells_;
};

}  // namespace rfm
