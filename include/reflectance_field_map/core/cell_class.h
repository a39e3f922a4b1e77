#pragma once

#include "reflectance_field_map/core/grid_geometry.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rfm {

// What the map says about a 2D cell.
enum class CellClass : uint8_t {
  kUnknown = 0,   // never observed
  kFree = 1,      // observed as missed and not an obstacle
  kStatic = 2,    // obstacle, widely visible (walls, frames, pane edges)
  kGlass = 3,     // obstacle, reflective only near its normal and attached to a static cell
  kMetal = 4,     // like glass, with a wider reflective lobe
  kMotion = 5,    // reflective evidence left by a moving object: not an obstacle
  kOccupied = 6,  // obstacle not yet classified by motion removal
};

inline bool isObstacle(CellClass c) {
  return c == CellClass::kStatic || c == CellClass::kGlass || c == CellClass::kMetal ||
         c == CellClass::kOccupied;
}

// Cells a ray cannot pass through without its return being untrustworthy (Alg. 3).
inline bool blocksRays(CellClass c) {
  return c == CellClass::kGlass || c == CellClass::kMetal || c == CellClass::kStatic;
}

// Obstacles that reflect only near their normal (Alg. 2's anchored, not widely visible cells).
inline bool isGlassOrMetal(CellClass c) {
  return c == CellClass::kGlass || c == CellClass::kMetal;
}

// Free or unknown: nothing a ray could stop at.
inline bool isEmptySpace(CellClass c) {
  return c == CellClass::kFree || c == CellClass::kUnknown;
}

// nav_msgs/OccupancyGrid value: -1 unknown, 0 free, 100 occupied; motion counts as free.
inline int8_t occupancyValue(CellClass c) {
  if (c == CellClass::kUnknown) return -1;
  return isObstacle(c) ? 100 : 0;
}

const char* toString(CellClass c);

// The class of `cell` in `classes` (row-major over `box`); unknown outside the box.
inline CellClass classInBox(const CellBox& box, const std::vector<CellClass>& classes,
                            const CellIndex& cell) {
  return box.contains(cell) ? classes[box.indexOf(cell)] : CellClass::kUnknown;
}

// The cells 8-connected to `start` in a row-major box of `width` x `height` cells, into `members`
// (depth first; `start` first). claim(index) takes a neighbour into the group: it returns false
// for a cell that is no member or was taken before, and marks the others taken. `start` must be
// taken already; `stack` is scratch.
template <typename Claim>
void collect8Connected(int width, int height, int start, Claim&& claim, std::vector<int>& stack,
                       std::vector<int>& members) {
  members.clear();
  stack.assign(1, start);
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    members.push_back(i);
    const int x = i % width, y = i / width;
    for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, height - 1); ++ny) {
      for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, width - 1); ++nx) {
        const int n = ny * width + nx;
        if (n != i && claim(n)) stack.push_back(n);
      }
    }
  }
}

}  // namespace rfm
