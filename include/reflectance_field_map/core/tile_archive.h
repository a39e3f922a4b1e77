#pragma once

#include "reflectance_field_map/core/grid_geometry.h"

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <unordered_map>
#include <vector>

namespace rfm {

// Zero-run-length coding of int8 bins: most bins of a tile were never observed (0).
// Format: a control byte c < 128 is followed by c + 1 literal bytes; c >= 128 stands for
// c - 127 zero bytes.
std::vector<uint8_t> compressBins(const int8_t* bins, size_t count);
// Decodes into `bins` (exactly `count` values); false when the data is corrupt.
bool decompressBins(const std::vector<uint8_t>& packed, int8_t* bins, size_t count);

// Theta-resolved evidence of tiles outside the active region, compressed, so that a revisited
// place keeps its reflectance history.
class TileArchive {
 public:
  void store(const TileIndex& tile, std::vector<uint8_t> packed);
  // Removes and returns the tile's packed bins; empty when the tile was never archived.
  std::vector<uint8_t> take(const TileIndex& tile);
  bool contains(const TileIndex& tile) const { return tiles_.count(key(tile)) > 0; }
  size_t tileCount() const { return tiles_.size(); }
  size_t bytes() const { return bytes_; }
  void clear();

  void write(std::ostream& out) const;
  // Replaces the archive with one written by write() for tiles of tile_cells x tile_cells cells
  // of theta_bins bins. False (and the archive unchanged) when an entry is larger than a tile's
  // bins can compress to, does not decode to exactly a tile's bins, lies where the global map's
  // cells may not (GlobalMap2D::kMaxCellCoordinate), comes twice, or the stream ends early.
  bool read(std::istream& in, int tile_cells, int theta_bins);

  // The most bytes compressBins makes of `count` bins: a control byte per 128 literals.
  static size_t maxPackedBytes(size_t count) { return count + (count + 127) / 128; }

  template <typename Visitor>
  void forEach(Visitor&& visit) const {
    for (const auto& entry : tiles_)
      visit(unkey(entry.first), entry.second);
  }

 private:
  static int64_t key(const TileIndex& tile) {
    // x in the high word by a multiply: a left shift of a negative value is undefined.
    return (static_cast<int64_t>(tile.x()) * (int64_t{1} << 32)) ^ static_cast<uint32_t>(tile.y());
  }
  static TileIndex unkey(int64_t key) {
    return {static_cast<int>(key >> 32), static_cast<int>(static_cast<uint32_t>(key))};
  }

  std::unordered_map<int64_t, std::vector<uint8_t>> tiles_;
  size_t bytes_ = 0;
};

}  // namespace rfm
