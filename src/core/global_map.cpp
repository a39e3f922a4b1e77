#include "reflectance_field_map/core/global_map.h"

#include <algorithm>
#include <cstdlib>
#include <istream>
#include <limits>
#include <ostream>

namespace rfm {

namespace {
constexpr uint32_t kMapMagic = 0x52464d47;  // "RFMG"
}

GlobalMap2D::GlobalMap2D(int tile_cells) : tile_cells_(tile_cells) {}

CellClass GlobalMap2D::get(const CellIndex& cell) const {
  // Beyond every tile (where the ends of long beams are judged): no hashing needed to tell.
  if (!bounds_.contains(cell)) return CellClass::kUnknown;
  const TileIndex tile = tileOf(cell);
  auto it = tiles_.find(key(tile));
  if (it == tiles_.end()) return CellClass::kUnknown;
  const int x = cell.x() - tile.x() * tile_cells_;
  const int y = cell.y() - tile.y() * tile_cells_;
  return it->second[y * tile_cells_ + x];
}

void GlobalMap2D::set(const CellIndex& cell, CellClass value) {
  const TileIndex tile = tileOf(cell);
  auto it = tiles_.find(key(tile));
  if (it == tiles_.end()) {
    if (value == CellClass::kUnknown) return;  // nothing to record
    Tile storage(new CellClass[static_cast<size_t>(tile_cells_) * tile_cells_]);
    std::fill(storage.get(), storage.get() + tile_cells_ * tile_cells_, CellClass::kUnknown);
    it = tiles_.emplace(key(tile), std::move(storage)).first;
    bounds_ = bounds_.unite({tile * tile_cells_, (tile + TileIndex(1, 1)) * tile_cells_});
  }
  CellClass& slot = it->second[(cell.y() - tile.y() * tile_cells_) * tile_cells_ +
                               (cell.x() - tile.x() * tile_cells_)];
  if (slot == value) return;
  slot = value;
  changed_ = changed_.unite({cell, cell + CellIndex(1, 1)});
}

CellBox GlobalMap2D::takeChangedBox() {
  const CellBox changed = changed_;
  changed_ = CellBox();
  return changed;
}

size_t GlobalMap2D::bytes() const {
  return tiles_.size() * (static_cast<size_t>(tile_cells_) * tile_cells_ + sizeof(Tile) + 32);
}

void GlobalMap2D::clear() {
  tiles_.clear();
  bounds_ = CellBox();
  changed_ = CellBox();
}

void GlobalMap2D::extract(const CellBox& box, std::vector<CellClass>& out) const {
  out.assign(static_cast<size_t>(std::max(0, box.width())) * std::max(0, box.height()),
             CellClass::kUnknown);
  if (box.empty()) return;
  const TileIndex first = tileOf(box.min);
  const TileIndex last = tileOf(box.max - CellIndex(1, 1));
  for (int ty = first.y(); ty <= last.y(); ++ty) {
    for (int tx = first.x(); tx <= last.x(); ++tx) {
      auto it = tiles_.find(key({tx, ty}));
      if (it == tiles_.end()) continue;
      const CellBox tile_box =
          CellBox{TileIndex(tx, ty) * tile_cells_, TileIndex(tx + 1, ty + 1) * tile_cells_}
              .intersect(box);
      for (int y = tile_box.min.y(); y < tile_box.max.y(); ++y) {
        const CellClass* row = &it->second[(y - ty * tile_cells_) * tile_cells_];
        for (int x = tile_box.min.x(); x < tile_box.max.x(); ++x) {
          out[static_cast<size_t>(y - box.min.y()) * box.width() + (x - box.min.x())] =
              row[x - tx * tile_cells_];
        }
      }
    }
  }
}

void GlobalMap2D::write(std::ostream& out) const {
  const uint32_t magic = kMapMagic;
  const int32_t tile_cells = tile_cells_;
  const uint64_t count = tiles_.size();
  out.write(reinterpret_cast<const char*>(&magic), sizeof(magic));
  out.write(reinterpret_cast<const char*>(&tile_cells), sizeof(tile_cells));
  out.write(reinterpret_cast<const char*>(&count), sizeof(count));
  for (const auto& entry : tiles_) {
    out.write(reinterpret_cast<const char*>(&entry.first), sizeof(entry.first));
    out.write(reinterpret_cast<const char*>(entry.second.get()),
              static_cast<std::streamsize>(tile_cells_) * tile_cells_);
  }
}

bool GlobalMap2D::read(std::istream& in) {
  uint32_t magic = 0;
  int32_t tile_cells = 0;
  uint64_t count = 0;
  if (!in.read(reinterpret_cast<char*>(&magic), sizeof(magic)) || magic != kMapMagic ||
      !in.read(reinterpret_cast<char*>(&tile_cells), sizeof(tile_cells)) ||
      tile_cells != tile_cells_ || !in.read(reinterpret_cast<char*>(&count), sizeof(count))) {
    return false;
  }
  // Tiles are read one at a time, each allocated only as its key is checked: the count itself
  // costs nothing until the data behind it is there.
  const size_t tile_bytes = static_cast<size_t>(tile_cells_) * tile_cells_;
  const int64_t tile_limit = kMaxCellCoordinate / tile_cells_;
  GlobalMap2D loaded(tile_cells_);
  for (uint64_t i = 0; i < count; ++i) {
    int64_t tile_key = 0;
    if (!in.read(reinterpret_cast<char*>(&tile_key), sizeof(tile_key))) return false;
    const int64_t tx = tile_key >> 32;  // arithmetic: the high word is signed
    const int64_t ty = static_cast<int32_t>(static_cast<uint32_t>(tile_key));
    if (tx < -tile_limit || tx >= tile_limit || ty < -tile_limit || ty >= tile_limit) {
      return false;
    }
    const TileIndex tile(static_cast<int>(tx), static_cast<int>(ty));
    Tile storage(new CellClass[tile_bytes]);
    if (!in.read(reinterpret_cast<char*>(storage.get()),
                 static_cast<std::streamsize>(tile_bytes))) {
      return false;
    }
    for (size_t c = 0; c < tile_bytes; ++c) {
      if (static_cast<uint8_t>(storage[c]) > static_cast<uint8_t>(CellClass::kOccupied)) {
        return false;
      }
    }
    if (!loaded.tiles_.emplace(key(tile), std::move(storage)).second) return false;  // twice
    loaded.bounds_ =
        loaded.bounds_.unite({tile * tile_cells_, (tile + TileIndex(1, 1)) * tile_cells_});
  }
  loaded.changed_ = loaded.bounds_;
  *this = std::move(loaded);
  return true;
}

}  // namespace rfm
