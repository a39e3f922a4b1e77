#include "reflectance_field_map/core/tile_archive.h"

#include "reflectance_field_map/core/global_map.h"

#include <istream>
#include <ostream>

namespace rfm {

std::vector<uint8_t> compressBins(const int8_t* bins, size_t count) {
  std::vector<uint8_t> out;
  size_t i = 0;
  while (i < count) {
    if (bins[i] == 0) {
      size_t run = 1;
      while (i + run < count && bins[i + run] == 0 && run < 128)
        ++run;
      out.push_back(static_cast<uint8_t>(127 + run));
      i += run;
      continue;
    }
    // Literals up to the next pair of zeros (a lone zero is cheaper kept as a literal).
    size_t run = 1;
    while (i + run < count && run < 128 &&
           !(bins[i + run] == 0 && (i + run + 1 >= count || bins[i + run + 1] == 0))) {
      ++run;
    }
    out.push_back(static_cast<uint8_t>(run - 1));
    for (size_t k = 0; k < run; ++k)
      out.push_back(static_cast<uint8_t>(bins[i + k]));
    i += run;
  }
  return out;
}

bool decompressBins(const std::vector<uint8_t>& packed, int8_t* bins, size_t count) {
  size_t written = 0, read = 0;
  while (read < packed.size()) {
    const uint8_t control = packed[read++];
    if (control >= 128) {
      const size_t run = control - 127u;
      if (written + run > count) return false;
      for (size_t k = 0; k < run; ++k)
        bins[written++] = 0;
    } else {
      const size_t run = control + 1u;
      if (written + run > count || read + run > packed.size()) return false;
      for (size_t k = 0; k < run; ++k)
        bins[written++] = static_cast<int8_t>(packed[read++]);
    }
  }
  return written == count;
}

void TileArchive::store(const TileIndex& tile, std::vector<uint8_t> packed) {
  auto& slot = tiles_[key(tile)];
  bytes_ -= slot.size();
  bytes_ += packed.size();
  slot = std::move(packed);
}

std::vector<uint8_t> TileArchive::take(const TileIndex& tile) {
  auto it = tiles_.find(key(tile));
  if (it == tiles_.end()) return {};
  std::vector<uint8_t> packed = std::move(it->second);
  bytes_ -= packed.size();
  tiles_.erase(it);
  return packed;
}

void TileArchive::clear() {
  tiles_.clear();
  bytes_ = 0;
}

void TileArchive::write(std::ostream& out) const {
  const uint64_t count = tiles_.size();
  out.write(reinterpret_cast<const char*>(&count), sizeof(count));
  for (const auto& entry : tiles_) {
    const int64_t tile_key = entry.first;
    const uint64_t size = entry.second.size();
    out.write(reinterpret_cast<const char*>(&tile_key), sizeof(tile_key));
    out.write(reinterpret_cast<const char*>(&size), sizeof(size));
    out.write(reinterpret_cast<const char*>(entry.second.data()),
              static_cast<std::streamsize>(size));
  }
}

bool TileArchive::read(std::istream& in, int tile_cells, int theta_bins) {
  if (tile_cells <= 0 || theta_bins <= 0) return false;
  uint64_t count = 0;
  if (!in.read(reinterpret_cast<char*>(&count), sizeof(count))) return false;
  const size_t tile_bins = static_cast<size_t>(tile_cells) * tile_cells * theta_bins;
  // Entries are checked one at a time before their bytes are allocated, so the count and the
  // sizes cost nothing until the data behind them is there.
  const uint64_t max_packed = maxPackedBytes(tile_bins);
  const int64_t limit = GlobalMap2D::kMaxCellCoordinate / tile_cells;
  TileArchive loaded;
  std::vector<int8_t> decoded(tile_bins);
  for (uint64_t i = 0; i < count; ++i) {
    int64_t tile_key = 0;
    uint64_t size = 0;
    if (!in.read(reinterpret_cast<char*>(&tile_key), sizeof(tile_key)) ||
        !in.read(reinterpret_cast<char*>(&size), sizeof(size)) || size == 0 || size > max_packed) {
      return false;
    }
    const int64_t tx = tile_key >> 32;  // arithmetic: the high word is signed
    const int64_t ty = static_cast<int32_t>(static_cast<uint32_t>(tile_key));
    if (tx < -limit || tx >= limit || ty < -limit || ty >= limit) return false;
    std::vector<uint8_t> packed(size);
    if (!in.read(reinterpret_cast<char*>(packed.data()), static_cast<std::streamsize>(size)) ||
        !decompressBins(packed, decoded.data(), decoded.size())) {
      return false;
    }
    const int64_t canonical = key({static_cast<int>(tx), static_cast<int>(ty)});
    if (loaded.tiles_.count(canonical) > 0) return false;  // the same tile twice
    loaded.bytes_ += size;
    loaded.tiles_.emplace(canonical, std::move(packed));
  }
  *this = std::move(loaded);
  return true;
}

}  // namespace rfm
