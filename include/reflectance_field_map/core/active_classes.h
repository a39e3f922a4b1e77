// The classes of the active region's cells, as the last motion removal left them.
#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/clearance_map.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/rolling_window.h"

#include <vector>

namespace rfm {

// The active region's cells classified (motion removal, glass completion): `box` row-major, x
// fastest. `unchanged_tiles` (by storage tile; empty: none) marks tiles whose classes are known
// to equal the last classification's, so that writing them again can be skipped.
struct ClassifiedRegion {
  CellBox box;
  std::vector<CellClass> classes;
  std::vector<uint8_t> unchanged_tiles;

  CellClass at(const CellIndex& cell) const { return classes[box.indexOf(cell)]; }
};

// The classes of the window's cells by storage index, and what the reflection check (Alg. 3)
// reads of them: whether any cell blocks rays, and the clearance of the cells that do. Cells
// outside the window have the classes of the global map (the explored map, which outlives the
// window).
class ActiveClasses {
 public:
  // `window` and `map` must outlive this; the clearance is kept in blocks of
  // 2^clearance_block_shift cells a side (ClearanceMap).
  ActiveClasses(const RollingWindow& window, const GlobalMap2D& map, int clearance_block_shift);

  // The class of any cell.
  CellClass at(const CellIndex& cell) const {
    return window_.contains(cell) ? classes_[window_.storageIndex(cell)] : map_.get(cell);
  }
  // The class of the window's cell at `storage_index`.
  CellClass atSlot(int storage_index) const { return classes_[storage_index]; }
  bool anyBlocking() const { return blocking_cells_ > 0; }
  // Distance to the nearest cell blocking rays, over the window's box.
  const ClearanceMap& clearance() const { return clearance_; }

  // The window moved (RollingWindow): its entering tiles take the classes the global map
  // remembers for them.
  void enter(const std::vector<TileIndex>& tiles);
  // Takes the region's classes; returns the box of the cells that block rays now and did not
  // before (new glass, metal or structure that is not static). Rows on the runner's threads.
  CellBox replace(const ClassifiedRegion& region, ParallelRunner* runner);
  // Every cell unknown: the next placement of the window loads its classes afresh.
  void clear();

  size_t bytes() const { return classes_.size() * sizeof(CellClass); }

 private:
  const RollingWindow& window_;
  const GlobalMap2D& map_;
  std::vector<CellClass> classes_;  // by storage index
  size_t blocking_cells_ = 0;
  ClearanceMap clearance_;
  std::vector<CellClass> entering_;  // enter(): a tile's classes from the global map
};

}  // namespace rfm
