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
  bool read(std::istream& in);

 private:
  using Tile = std::unique_ptr<CellClass[]>;
  static int64_t key(const TileIndex& tile) {
    return (static_cast<int64_t>(tile.x()) << 32) ^ static_cast<uint32_t>(tile.y());
  }
  TileIndex tileOf(const CellIndex& cell) const {
    return {floorDiv(cell.x(), tile_cells_), floorDiv(cell.y(), tile_cells_)};
  }

  int tile_cells_;
  std::unordered_map<int64_t, Tile> tiles_;
  CellBox bounds_;
  CellBox changed_;
};

}  // namespace rfm
