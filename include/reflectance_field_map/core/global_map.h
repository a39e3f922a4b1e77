#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/grid_geometry.h"

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <unordered_map>
#include <vector>

namespace rfm {

// The 2D map of everything explored: one byte (a CellClass) per cell, in tiles allocated as
// exploration reaches them, so it grows without ever copying what exists.
class GlobalMap2D {
 public:
  explicit GlobalMap2D(int tile_cells = 64);

  int tileCells() const { return tile_cells_; }
  CellClass get(const CellIndex& cell) const;
  void set(const CellIndex& cell, CellClass value);

  // Sets every cell of `box` to class_of(cell), tile by tile (no per-cell hashing).
  template <typename ClassOf>
  void assign(const CellBox& box, ClassOf&& class_of);

  // Bounding box of all allocated tiles (empty when nothing was set).
  CellBox bounds() const { return bounds_; }
  // Box of cells changed since the last takeChangedBox().
  CellBox takeChangedBox();
  size_t tileCount() const { return tiles_.size(); }
  size_t bytes() const;
  void clear();

  // Copies `box` row-major (x fastest) into `out`, unknown outside allocated tiles.
  void extract(const CellBox& box, std::vector<CellClass>& out) const;

  void write(std::ostream& out) const;
  // Replaces the map with one written by write(); false (and the map unchanged) when the stream
  // holds another tile size, a tile twice, a class that does not exist, a tile whose cells lie
  // beyond kMaxCellCoordinate, or ends early.
  bool read(std::istream& in);

  // Cells read from a file lie within [-kMaxCellCoordinate, kMaxCellCoordinate) on both axes, so
  // that every box of them, and its width, fits an int.
  static constexpr int kMaxCellCoordinate = 1 << 28;

 private:
  using Tile = std::unique_ptr<CellClass[]>;
  static int64_t key(const TileIndex& tile) {
    // x in the high word by a multiply: a left shift of a negative value is undefined.
    return (static_cast<int64_t>(tile.x()) * (int64_t{1} << 32)) ^ static_cast<uint32_t>(tile.y());
  }
  TileIndex tileOf(const CellIndex& cell) const {
    return {floorDiv(cell.x(), tile_cells_), floorDiv(cell.y(), tile_cells_)};
  }

  int tile_cells_;
  std::unordered_map<int64_t, Tile> tiles_;
  CellBox bounds_;
  CellBox changed_;
};

template <typename ClassOf>
void GlobalMap2D::assign(const CellBox& box, ClassOf&& class_of) {
  if (box.empty()) return;
  const TileIndex first = tileOf(box.min);
  const TileIndex last = tileOf(box.max - CellIndex(1, 1));
  for (int ty = first.y(); ty <= last.y(); ++ty) {
    for (int tx = first.x(); tx <= last.x(); ++tx) {
      const TileIndex tile(tx, ty);
      const CellBox part =
          CellBox{tile * tile_cells_, (tile + TileIndex(1, 1)) * tile_cells_}.intersect(box);
      auto it = tiles_.find(key(tile));
      CellClass* cells = it == tiles_.end() ? nullptr : it->second.get();
      for (int y = part.min.y(); y < part.max.y(); ++y) {
        for (int x = part.min.x(); x < part.max.x(); ++x) {
          const CellClass value = class_of(CellIndex(x, y));
          if (cells == nullptr) {
            if (value == CellClass::kUnknown) continue;
            set({x, y}, value);  // allocates the tile
            cells = tiles_.find(key(tile))->second.get();
            continue;
          }
          CellClass& slot = cells[(y - ty * tile_cells_) * tile_cells_ + (x - tx * tile_cells_)];
          if (slot == value) continue;
          slot = value;
          changed_ = changed_.unite({{x, y}, {x + 1, y + 1}});
        }
      }
    }
  }
}

}  // namespace rfm
