#include "reflectance_field_map/core/rolling_window.h"

namespace rfm {

RollingWindow::RollingWindow(int tile_cells, int tiles_per_side)
    : tile_cells_(tile_cells),
      tile_shift_(__builtin_ctz(static_cast<unsigned>(tile_cells))),
      tile_mask_(tile_cells - 1),
      tiles_per_side_(tiles_per_side) {
  const int size = sizeCells();
  column_offsets_.resize(4 * static_cast<size_t>(size));
  row_offsets_.resize(4 * static_cast<size_t>(size));
  for (int i = 0; i < 4 * size; ++i) {
    column_offsets_[i] = storageSlot(i % size, 0);
    row_offsets_[i] = storageSlot(0, i % size);
  }
  setOrigin(origin_tile_);  // derives the tables' base for the initial origin
}

void RollingWindow::setOrigin(const TileIndex& origin_tile) {
  origin_tile_ = origin_tile;
  const CellIndex first = origin_tile * tile_cells_;
  const int size = sizeCells();
  box_ = {first, first + CellIndex(size, size)};
  // A multiple of the window size, one window below the one holding the box's first cell.
  offset_origin_ = {first.x() - storageCoordinate(first.x()) - size,
                    first.y() - storageCoordinate(first.y()) - size};
}

std::vector<TileIndex> RollingWindow::tiles() const {
  std::vector<TileIndex> out;
  out.reserve(static_cast<size_t>(tiles_per_side_) * tiles_per_side_);
  for (int y = 0; y < tiles_per_side_; ++y) {
    for (int x = 0; x < tiles_per_side_; ++x)
      out.push_back(origin_tile_ + TileIndex(x, y));
  }
  return out;
}

WindowShift diffWindows(const RollingWindow& from, const TileIndex& new_origin) {
  WindowShift shift;
  const TileIndex old_origin = from.originTile();
  if (old_origin == new_origin) return shift;
  shift.moved = true;
  const int n = from.tilesPerSide();
  auto inside = [n](const TileIndex& tile, const TileIndex& origin) {
    const TileIndex d = tile - origin;
    return d.x() >= 0 && d.y() >= 0 && d.x() < n && d.y() < n;
  };
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const TileIndex old_tile = old_origin + TileIndex(x, y);
      if (!inside(old_tile, new_origin)) shift.left.push_back(old_tile);
      const TileIndex new_tile = new_origin + TileIndex(x, y);
      if (!inside(new_tile, old_origin)) shift.entered.push_back(new_tile);
    }
  }
  return shift;
}

}  // namespace rfm
