#include "reflectance_field_map/core/active_classes.h"

namespace rfm {

ActiveClasses::ActiveClasses(const RollingWindow& window, const GlobalMap2D& map,
                             int clearance_block_shift)
    : window_(window),
      map_(map),
      classes_(static_cast<size_t>(window.sizeCells()) * window.sizeCells(), CellClass::kUnknown),
      clearance_(clearance_block_shift) {}

void ActiveClasses::enter(const std::vector<TileIndex>& tiles) {
  // A tile at a time: a batch's window enters whole, every pass.
  for (const TileIndex& tile : tiles) {
    const CellBox box = window_.tileBox(tile);
    map_.extract(box, entering_);
    size_t i = 0;
    for (int y = box.min.y(); y < box.max.y(); ++y) {
      for (int x = box.min.x(); x < box.max.x(); ++x)
        classes_[window_.storageIndex({x, y})] = entering_[i++];
    }
  }
  const CellBox box = window_.box();
  clearance_.compute(box, [&](int dx, int dy) {
    return !blocksRays(classes_[window_.storageIndex(box.min + CellIndex(dx, dy))]);
  });
}

CellBox ActiveClasses::replace(const ClassifiedRegion& region, ParallelRunner* runner) {
  const CellBox& box = region.box;
  auto unchanged = [&](int slot) {
    return !region.unchanged_tiles.empty() &&
           region.unchanged_tiles[slot >> window_.tileSlotShift()] != 0;
  };
  struct alignas(64) RowResult {
    size_t blocking = 0;
    CellBox new_glass;
    bool blocking_changed = false;  // a cell started or stopped blocking rays
  };
  std::vector<RowResult> rows(box.height());
  parallelFor(runner, rows.size(), 16, [&](size_t row, int) {
    const int y = box.min.y() + static_cast<int>(row);
    RowResult& result = rows[row];
    window_.forEachTileSpan(
        {{box.min.x(), y}, {box.max.x(), y + 1}}, [&](int, int x_begin, int x_end, int slot) {
          // An unchanged tile's cells, free or unknown, are stored already.
          if (unchanged(slot)) return;
          size_t i = row * box.width() + (x_begin - box.min.x());
          for (int x = x_begin; x < x_end; ++x, ++slot) {
            CellClass& stored = classes_[slot];
            const CellClass now = region.classes[i++];
            if (blocksRays(now)) {
              ++result.blocking;
              if (!blocksRays(stored) && now != CellClass::kStatic) {
                result.new_glass = result.new_glass.unite({{x, y}, {x + 1, y + 1}});
              }
            }
            result.blocking_changed |= blocksRays(stored) != blocksRays(now);
            stored = now;
          }
        });
  });
  CellBox new_glass;
  bool blocking_changed = false;
  blocking_cells_ = 0;
  for (const RowResult& result : rows) {
    blocking_cells_ += result.blocking;
    new_glass = new_glass.unite(result.new_glass);
    blocking_changed |= result.blocking_changed;
  }
  if (blocking_changed || clearance_.box().min != box.min || clearance_.box().max != box.max) {
    clearance_.compute(box, [&](int dx, int dy) {
      return !blocksRays(region.classes[static_cast<size_t>(dy) * box.width() + dx]);
    });
  }
  return new_glass;
}

void ActiveClasses::clear() {
  std::fill(classes_.begin(), classes_.end(), CellClass::kUnknown);
  blocking_cells_ = 0;
  clearance_.clear();
}

}  // namespace rfm
