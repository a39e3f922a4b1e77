#include "reflectance_field_map/core/reflectance_field.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <istream>
#include <ostream>

namespace rfm {
namespace {

constexpr uint32_t kStateMagic = 0x52464d31;  // "RFM1"

template <typename T>
void writeValue(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}
template <typename T>
bool readValue(std::istream& in, T& value) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&value), sizeof(T)));
}

// Huge pages for a window whose slices take at most this much. A 2 MB page of a slice spans the
// window's width over many rows, so the first ray to reach it brings all of it in: an offline
// window over a campus (4 GiB of slices) would be resident almost whole, most of it never
// reached, and no faster for it (the kernel zeroes every page). A robot-centred window (32 MiB)
// or one over a building is reached nearly everywhere, and there the fewer page translations pay.
constexpr size_t kHugePageSliceBytes = size_t{512} << 20;

}  // namespace

int activeWindowTiles(double radius, double resolution, int tile_cells) {
  // The robot may be anywhere in the centre tile: each side needs ceil(radius / tile) tiles.
  const int side_tiles = static_cast<int>(std::ceil(radius / (tile_cells * resolution) - 1e-9));
  return 2 * side_tiles + 1;
}

ReflectanceField::ReflectanceField(const GridOptions& grid, const LogOddsOptions& log_odds,
                                   const ActiveRegionOptions& region, double window_radius)
    : geometry_(grid.resolution, grid.theta_bins),
      log_odds_(log_odds),
      window_(grid.tile_cells,
              activeWindowTiles(std::max(region.active_region_radius, window_radius),
                                grid.resolution, grid.tile_cells)),
      theta_bins_(grid.theta_bins),
      plane_(static_cast<size_t>(window_.sizeCells()) * window_.sizeCells()),
      mask_words_((grid.theta_bins + 63) / 64),
      bins_(plane_ * theta_bins_,
            plane_ * theta_bins_ <= kHugePageSliceBytes ? PageKind::kHuge : PageKind::kOrdinary),
      reflective_masks_(plane_ * mask_words_, bins_.pages()),
      missed_bins_(plane_, bins_.pages()),
      hit_flags_(plane_, bins_.pages()),
      confident_miss_since_tick_(plane_, bins_.pages()),
      reflective_bins_(plane_, bins_.pages()),
      tile_reflective_cells_(window_.storageTiles(), 0),
      tile_versions_(window_.storageTiles(), 0),
      tick_pending_(window_.storageTiles(), 0) {}

ReflectanceField::Identity::Identity() {
  static std::atomic<uint64_t> next{1};
  value = next++;
}

WindowShift ReflectanceField::recenter(const Eigen::Vector2d& robot_position,
                                       ParallelRunner* runner) {
  const TileIndex origin = window_.originCentredOn(geometry_.cellOf(robot_position));
  if (!centred_) {
    // First placement: everything enters (a loaded archive may hold some of it).
    centred_ = true;
    window_.setOrigin(origin);
    WindowShift shift;
    shift.moved = true;
    shift.entered = window_.tiles();
    restoreTiles(shift.entered, runner);
    return shift;
  }
  WindowShift shift = diffWindows(window_, origin);
  if (!shift.moved) return shift;
  archiveTiles(shift.left, runner);
  window_.setOrigin(origin);
  restoreTiles(shift.entered, runner);
  return shift;
}

void ReflectanceField::archiveTiles(const std::vector<TileIndex>& tiles, ParallelRunner* runner) {
  // Tiles are gathered, compressed and cleared side by side; the archive itself is one map.
  std::vector<std::vector<uint8_t>> packed(tiles.size());
  parallelFor(runner, tiles.size(), 1, [&](size_t i, int) {
    // The cell summaries count every bin off the prior, so a tile they call empty holds nothing
    // to keep and its bins are already clear: most of a window's tiles, at long range.
    const bool observed = tileHoldsEvidence(tiles[i]);
    if (observed) {
      std::vector<int8_t> bins;
      gatherTile(tiles[i], bins);
      packed[i] = compressBins(bins.data(), bins.size());
    }
    clearTileStorage(tiles[i], observed);
  });
  for (size_t i = 0; i < tiles.size(); ++i) {
    if (!packed[i].empty()) {
      archive_.store(tiles[i], std::move(packed[i]));
    } else {
      archive_.take(tiles[i]);  // drop a stale copy, if any
    }
  }
}

void ReflectanceField::restoreTiles(const std::vector<TileIndex>& tiles, ParallelRunner* runner) {
  std::vector<std::vector<uint8_t>> packed(tiles.size());
  for (size_t i = 0; i < tiles.size(); ++i)
    packed[i] = archive_.take(tiles[i]);
  parallelFor(runner, tiles.size(), 1, [&](size_t i, int) {
    if (packed[i].empty()) return;  // never observed: storage is already clear
    std::vector<int8_t> bins(static_cast<size_t>(window_.tileCells()) * window_.tileCells() *
                             theta_bins_);
    if (!decompressBins(packed[i], bins.data(), bins.size())) return;  // corrupt: start afresh
    scatterTile(tiles[i], bins);
    rebuildSummaries(tiles[i]);
  });
}

int ReflectanceField::reflectiveBins(const CellIndex& cell) const {
  return countMaskBits(reflectiveMask(cell), mask_words_);
}

double ReflectanceField::marginalOdds(const CellIndex& cell) const {
  return marginalOddsAt(window_.storageIndex(cell));
}

bool ReflectanceField::reflectsNearAxisAt(int storage_index, const Eigen::Vector2d& axis,
                                          double max_off) const {
  const double min_cos = std::cos(max_off);
  bool near = false;
  forEachMaskBit(reflectiveMaskAt(storage_index), mask_words_, [&](int bin) {
    const double angle = geometry_.binCenter(bin);
    near |= std::abs(std::cos(angle) * axis.x() + std::sin(angle) * axis.y()) >= min_cos;
  });
  return near;
}

double ReflectanceField::marginalOddsAt(int storage_index) const {
  const size_t index = storage_index;
  double sum = 0.0;
  for (int bin = 0; bin < theta_bins_; ++bin)
    sum += log_odds_.odds(bins_[bin * plane_ + index]);
  return sum * geometry_.binWidth();
}

double ReflectanceField::reflectiveOddsAt(int storage_index) const {
  const uint64_t* mask = reflectiveMaskAt(storage_index);
  double sum = 0.0;
  forEachMaskBit(mask, mask_words_,
                 [&](int bin) { sum += log_odds_.odds(bins_[bin * plane_ + storage_index]); });
  return sum;
}

size_t ReflectanceField::activeBytes() const {
  return bins_.size() * sizeof(int8_t) + reflective_masks_.size() * sizeof(uint64_t) +
         missed_bins_.size() * sizeof(uint16_t) + hit_flags_.size() +
         confident_miss_since_tick_.size() + reflective_bins_.size() * sizeof(uint16_t) +
         tile_reflective_cells_.size() * sizeof(int) + tile_versions_.size() * sizeof(uint32_t);
}

void ReflectanceField::clear() {
  if (bins_.pages() == PageKind::kOrdinary) {
    // A large window: rays reach a few of each tile's slices, and most pages of the slices no
    // ray reached are still unmapped. Fresh zero pages keep them so, where zeros written over
    // every slice of each reached tile would bring them in (the campus: 2.8 against 1.5 GB).
    bins_ = ZeroedHugeArray<int8_t>(bins_.size(), bins_.pages());
    reflective_masks_ = ZeroedHugeArray<uint64_t>(reflective_masks_.size(), bins_.pages());
  } else {
    // Huge pages: the passes reach them nearly all. Zeros written in place over the tiles that
    // hold evidence cost less than faulting the window in again for the next batch pass (the
    // kernel zeroes, and compacts memory for, every huge page).
    const size_t cells = static_cast<size_t>(window_.tileCells()) * window_.tileCells();
    for (size_t first = 0; first < plane_; first += cells) {
      if (!slotsHoldEvidence(first, cells)) continue;
      for (int bin = 0; bin < theta_bins_; ++bin)
        std::fill_n(&bins_[bin * plane_ + first], cells, 0);
      std::fill_n(&reflective_masks_[first * mask_words_], cells * mask_words_, 0);
    }
  }
  // The cell summaries are far smaller than the slices: zeroed in place where set (after the
  // slices, whose clearing reads them), their written pages stay resident for the next pass.
  missed_bins_.zeroWhereSet();
  hit_flags_.zeroWhereSet();
  confident_miss_since_tick_.zeroWhereSet();
  reflective_bins_.zeroWhereSet();
  std::fill(tile_reflective_cells_.begin(), tile_reflective_cells_.end(), 0);
  std::fill(tick_pending_.begin(), tick_pending_.end(), 0);
  for (uint32_t& version : tile_versions_)
    ++version;
  archive_.clear();
  centred_ = false;
}

void ReflectanceField::gatherTile(const TileIndex& tile, std::vector<int8_t>& bins) const {
  const size_t cells = static_cast<size_t>(window_.tileCells()) * window_.tileCells();
  const size_t first = window_.tileFirstSlot(tile);
  bins.resize(cells * theta_bins_);
  for (int bin = 0; bin < theta_bins_; ++bin) {
    const int8_t* src = &bins_[bin * plane_ + first];
    std::copy(src, src + cells, &bins[bin * cells]);
  }
}

void ReflectanceField::scatterTile(const TileIndex& tile, const std::vector<int8_t>& bins) {
  const size_t cells = static_cast<size_t>(window_.tileCells()) * window_.tileCells();
  const size_t first = window_.tileFirstSlot(tile);
  for (int bin = 0; bin < theta_bins_; ++bin) {
    std::copy(&bins[bin * cells], &bins[bin * cells] + cells, &bins_[bin * plane_ + first]);
  }
}

bool ReflectanceField::tileHoldsEvidence(const TileIndex& tile) const {
  const size_t cells = static_cast<size_t>(window_.tileCells()) * window_.tileCells();
  return slotsHoldEvidence(window_.tileFirstSlot(tile), cells);
}

bool ReflectanceField::slotsHoldEvidence(size_t first, size_t count) const {
  // The cell summaries count every bin off the prior (reflective above it, missed below).
  for (size_t slot = first; slot < first + count; ++slot) {
    if (reflective_bins_[slot] != 0 || missed_bins_[slot] != 0) return true;
  }
  return false;
}

void ReflectanceField::clearTileStorage(const TileIndex& tile, bool bins_too) {
  const size_t cells = static_cast<size_t>(window_.tileCells()) * window_.tileCells();
  const size_t first = window_.tileFirstSlot(tile);
  if (bins_too) {
    for (int bin = 0; bin < theta_bins_; ++bin)
      std::fill_n(&bins_[bin * plane_ + first], cells, 0);
  }
  std::fill_n(&missed_bins_[first], cells, 0);
  std::fill_n(&hit_flags_[first], cells, 0);
  std::fill_n(&confident_miss_since_tick_[first], cells, 0);
  std::fill_n(&reflective_bins_[first], cells, 0);
  std::fill_n(&reflective_masks_[first * mask_words_], cells * mask_words_, 0);
  const int storage_tile = window_.storageTile(tile);
  tile_reflective_cells_[storage_tile] = 0;
  ++tile_versions_[storage_tile];
}

void ReflectanceField::rebuildSummaries(const TileIndex& tile) {
  // Slice by slice over the tile's contiguous cells (cell by cell would stride across slices).
  const size_t cells = static_cast<size_t>(window_.tileCells()) * window_.tileCells();
  const size_t first = window_.tileFirstSlot(tile);
  uint64_t* const masks = &reflective_masks_[first * mask_words_];
  std::fill_n(masks, cells * mask_words_, 0);
  std::vector<uint16_t> reflective(cells, 0), missed(cells, 0);
  for (int bin = 0; bin < theta_bins_; ++bin) {
    const int8_t* values = &bins_[bin * plane_ + first];
    const int word = bin >> 6, shift = bin & 63;
    for (size_t c = 0; c < cells; ++c) {
      const bool is_reflective = values[c] > 0;
      reflective[c] += is_reflective;
      missed[c] += values[c] < 0;
      masks[c * mask_words_ + word] |= static_cast<uint64_t>(is_reflective) << shift;
    }
  }
  int reflective_cells = 0;
  for (size_t c = 0; c < cells; ++c) {
    reflective_bins_[first + c] = reflective[c];
    missed_bins_[first + c] = missed[c];
    if (reflective[c] != 0) hit_flags_[first + c] |= kEverHit;
    reflective_cells += reflective[c] != 0;
  }
  const int storage_tile = window_.storageTile(tile);
  tile_reflective_cells_[storage_tile] = reflective_cells;
  tick_pending_[storage_tile] = 1;
  ++tile_versions_[storage_tile];
}

void ReflectanceField::applySummaryChanges(std::vector<DeferredSummaries>& writers,
                                           ParallelRunner* runner) {
  if (writers.empty()) return;
  const size_t parts = static_cast<size_t>(writers.front().parts);
  const size_t tiles = window_.storageTiles();
  const size_t tile_slots = size_t{1} << window_.tileSlotShift();
  // Writers that summed missed counts for this field (the others never wrote to it).
  std::vector<DeferredSummaries*> summed;
  size_t work = 0;  // changes listed, and cells of tiles with sums
  for (DeferredSummaries& writer : writers) {
    work += writer.size();
    if (writer.touched.size() != tiles || writer.missed.size() != plane_) continue;
    summed.push_back(&writer);
    work += tile_slots * static_cast<size_t>(
                             std::count(writer.touched.begin(), writer.touched.end(), uint8_t{1}));
  }
  // Part p takes list p and the tiles t with t & (parts - 1) == p, as the lists split them.
  auto apply_part = [&](size_t part, int) {
    for (const DeferredSummaries& writer : writers) {
      for (const SummaryChange& c : writer.lists[part])
        applySummaryChange(c.slot, c.bin, c.reflective, /*missed=*/0);
    }
    for (size_t tile = part; tile < tiles; tile += parts) {
      const size_t first = tile * tile_slots;
      uint16_t* const counts = &missed_bins_[first];
      bool touched = false;
      for (DeferredSummaries* writer : summed) {
        if (!writer->touched[tile]) continue;
        touched = true;
        // Counts come out right modulo 2^16, whatever the sums between.
        uint16_t* const sums = &writer->missed[first];
        for (size_t i = 0; i < tile_slots; ++i)
          counts[i] = static_cast<uint16_t>(counts[i] + sums[i]);
        // Consumed: empty for the writer's next changes.
        std::fill_n(sums, tile_slots, uint16_t{0});
        writer->touched[tile] = 0;
      }
      if (touched) ++tile_versions_[tile];
    }
  };
  // A scan's few changes (online) are not worth waking a helper for.
  constexpr size_t kMinWorkToShare = 4096;
  if (work < kMinWorkToShare) runner = nullptr;
  parallelFor(runner, parts, 1, apply_part);
}

void ReflectanceField::revertAt(int storage_index, int bin, int step) {
  // Clamping makes exact inversion impossible (a miss at the lower clamp changed nothing), so a
  // revert never moves a bin across the prior: it can under-correct, never invent.
  int8_t& v = bins_[static_cast<size_t>(bin) * plane_ + storage_index];
  const int shifted = std::clamp(v + step, log_odds_.minValue(), log_odds_.maxValue());
  // Never cross (or leave) the prior: that would turn "seen empty" into "seen reflective".
  const int updated = v < 0 ? std::min(shifted, 0) : (v > 0 ? std::max(shifted, 0) : 0);
  if (updated == v) return;
  const int old = v;
  v = static_cast<int8_t>(updated);
  // Every change marks the tile for the persistence tick and moves its version: readers of both
  // look at the bins' values, not only at the summaries. Those change only when the bin reaches
  // the prior: reflective, or missed, in one bin fewer.
  const int tile = storage_index >> window_.tileSlotShift();
  tick_pending_[tile] = 1;
  ++tile_versions_[tile];
  if (updated == 0) applySummaryChange(storage_index, bin, old > 0 ? -1 : 0, old < 0 ? -1 : 0);
}

void ReflectanceField::write(std::ostream& out) const {
  writeValue(out, kStateMagic);
  writeValue(out, static_cast<int32_t>(theta_bins_));
  writeValue(out, static_cast<int32_t>(window_.tileCells()));
  writeValue(out, geometry_.resolution());
  // Active tiles are written like archived ones, so a load restores them when re-centring.
  TileArchive all = archive_;
  if (centred_) {
    std::vector<int8_t> bins;
    for (const TileIndex& tile : window_.tiles()) {
      if (!tileHoldsEvidence(tile)) continue;
      gatherTile(tile, bins);
      all.store(tile, compressBins(bins.data(), bins.size()));
    }
  }
  all.write(out);
}

bool ReflectanceField::read(std::istream& in) {
  uint32_t magic = 0;
  int32_t bins = 0, tile_cells = 0;
  double resolution = 0.0;
  if (!readValue(in, magic) || magic != kStateMagic || !readValue(in, bins) ||
      !readValue(in, tile_cells) || !readValue(in, resolution) || bins != theta_bins_ ||
      tile_cells != window_.tileCells() || resolution != geometry_.resolution()) {
    return false;
  }
  TileArchive loaded;
  if (!loaded.read(in, tile_cells, bins)) return false;
  clear();
  archive_ = std::move(loaded);
  return true;
}

}  // namespace rfm
