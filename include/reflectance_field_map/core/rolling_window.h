#pragma once

#include "reflectance_field_map/core/grid_geometry.h"

#include <algorithm>
#include <vector>

namespace rfm {

// Geometry of a square window of tiles that follows the robot, stored as a circular buffer:
// a global cell c lives in storage slot positiveMod(c, size) on each axis, so moving the
// window only re-assigns the slots of tiles that scrolled out to the tiles that scrolled in.
class RollingWindow {
 public:
  RollingWindow(int tile_cells, int tiles_per_side);

  int tileCells() const { return tile_cells_; }
  int tilesPerSide() const { return tiles_per_side_; }
  int sizeCells() const { return tiles_per_side_ * tile_cells_; }
  const TileIndex& originTile() const { return origin_tile_; }
  // Cells of the window now (kept with the origin: class lookups test it for every cell).
  const CellBox& box() const { return box_; }
  bool contains(const CellIndex& cell) const { return box_.contains(cell); }

  int storageCoordinate(int cell) const { return positiveMod(cell, sizeCells()); }
  // Storage is tile-major: the cells of one tile are contiguous (row-major inside the tile), so
  // a ray touches few cache lines and a tile is archived or cleared as one block.
  int storageSlot(int storage_x, int storage_y) const {
    return (((storage_y >> tile_shift_) * tiles_per_side_ + (storage_x >> tile_shift_))
            << (2 * tile_shift_)) |
           ((storage_y & tile_mask_) << tile_shift_) | (storage_x & tile_mask_);
  }
  // The slot split by axis: storageIndex({x, y}) == columnOffsets()[x - offsetOrigin().x()] +
  // rowOffsets()[y - offsetOrigin().y()] (the bits x and y set in a tile-major index are
  // disjoint) for every cell of the window and up to a window beyond it. Walks inside the window
  // thus wrap around storage by indexing, without a branch or a modulo, and a cell that rounding
  // puts just outside still lands in the tables.
  const int* columnOffsets() const { return column_offsets_.data(); }
  const int* rowOffsets() const { return row_offsets_.data(); }
  const CellIndex& offsetOrigin() const { return offset_origin_; }
  // Storage slot of a cell inside the window (any cell maps to some slot).
  int storageIndex(const CellIndex& cell) const {
    const unsigned x = static_cast<unsigned>(cell.x() - offset_origin_.x());
    const unsigned y = static_cast<unsigned>(cell.y() - offset_origin_.y());
    const unsigned tabulated = static_cast<unsigned>(column_offsets_.size());
    if (x < tabulated && y < tabulated) return column_offsets_[x] + row_offsets_[y];
    return storageSlot(storageCoordinate(cell.x()), storageCoordinate(cell.y()));
  }
  // First slot of a tile inside the window: its cells are [first, first + tileCells()^2).
  int tileFirstSlot(const TileIndex& tile) const { return storageIndex(tile * tile_cells_); }
  TileIndex tileOf(const CellIndex& cell) const {
    return {floorDiv(cell.x(), tile_cells_), floorDiv(cell.y(), tile_cells_)};
  }
  CellBox tileBox(const TileIndex& tile) const {
    return {tile * tile_cells_, (tile + TileIndex(1, 1)) * tile_cells_};
  }
  // The origin that puts `center_cell`'s tile in the middle of the window.
  TileIndex originCentredOn(const CellIndex& center_cell) const {
    return tileOf(center_cell) - TileIndex(tiles_per_side_ / 2, tiles_per_side_ / 2);
  }
  // Tiles inside the window now.
  std::vector<TileIndex> tiles() const;

  // Calls visit(cell_x, cell_y, slot) for every cell of `box` (inside the window), row by row,
  // stepping storage coordinates instead of dividing per cell.
  template <typename Visit>
  void forEachCell(const CellBox& box, Visit&& visit) const {
    const int size = sizeCells();
    const int first_x = storageCoordinate(box.min.x());
    for (int y = box.min.y(); y < box.max.y(); ++y) {
      const int sy = storageCoordinate(y);
      int sx = first_x;
      for (int x = box.min.x(); x < box.max.x(); ++x) {
        visit(x, y, storageSlot(sx, sy));
        if (++sx == size) sx = 0;
      }
    }
  }

  // Calls visit(y, x_begin, x_end, first_slot) for each piece of a row of `box` (inside the
  // window) that lies in one tile: its cells occupy the consecutive slots
  // [first_slot, first_slot + x_end - x_begin), and first_slot >> tileSlotShift() is the tile.
  template <typename Visit>
  void forEachTileSpan(const CellBox& box, Visit&& visit) const {
    for (int y = box.min.y(); y < box.max.y(); ++y) {
      const int sy = storageCoordinate(y);
      for (int x = box.min.x(); x < box.max.x();) {
        const int x_end = std::min(box.max.x(), (floorDiv(x, tile_cells_) + 1) * tile_cells_);
        visit(y, x, x_end, storageSlot(storageCoordinate(x), sy));
        x = x_end;
      }
    }
  }
  // Storage tile of a slot: slot >> tileSlotShift() (tiles are contiguous blocks of slots).
  int tileSlotShift() const { return 2 * tile_shift_; }
  // The cell of the window now stored in `slot` (storageIndex's inverse over the box).
  CellIndex cellOfSlot(int slot) const {
    const int tile = slot >> tileSlotShift();
    const int storage_x = ((tile % tiles_per_side_) << tile_shift_) | (slot & tile_mask_);
    const int storage_y =
        ((tile / tiles_per_side_) << tile_shift_) | ((slot >> tile_shift_) & tile_mask_);
    return {box_.min.x() + positiveMod(storage_x - storageCoordinate(box_.min.x()), sizeCells()),
            box_.min.y() + positiveMod(storage_y - storageCoordinate(box_.min.y()), sizeCells())};
  }
  int storageTile(const TileIndex& tile) const { return tileFirstSlot(tile) >> tileSlotShift(); }
  int storageTiles() const { return tiles_per_side_ * tiles_per_side_; }

  void setOrigin(const TileIndex& origin_tile);

 private:
  int tile_cells_;  // a power of two
  int tile_shift_;
  int tile_mask_;
  int tiles_per_side_;
  TileIndex origin_tile_{0, 0};
  CellBox box_;
  // The cell at index 0 of the offset tables, which span four windows: the box maps into the
  // middle two, a window from either end. Set with the origin (setOrigin).
  CellIndex offset_origin_;
  std::vector<int> column_offsets_, row_offsets_;
};

// What a re-centring did: tiles that left the window and tiles that entered it.
struct WindowShift {
  bool moved = false;
  std::vector<TileIndex> left;
  std::vector<TileIndex> entered;  // newly exposed region, as tiles
};

// Tiles of `from` not in `to`, and of `to` not in `from`.
WindowShift diffWindows(const RollingWindow& from, const TileIndex& new_origin);

}  // namespace rfm
