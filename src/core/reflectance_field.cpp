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

}  // namespace

int activeWindowTiles(double radius, double resolution, int tile_cells) {
  // The robot may be anywhere in the centre tile: each side needs ceil(radius / tile) tiles.
  const int side_tiles = static_cast<int>(std::ceil(radius / (tile_cells * resolution) - 1e-9));
  return 2 * side_tiles + 1;
}

ReflectanceField::ReflectanceField(const GridOptions& grid, const LogOddsOptions& log_odds,
                                   const ActiveRegionOptions& region)
    : geometry_(grid.resolution, grid.theta_bins),
      log_odds_(log_odds),
      window_(grid.tile_cells,
              activeWindowTiles(region.windowRadius(), grid.resolution, grid.tile_cells)),
      theta_bins_(grid.theta_bins),
      plane_(static_cast<size_t>(window_.sizeCells()) * window_.sizeCells()),
      mask_words_((grid.theta_bins + 63) / 64),
      bins_(plane_ * theta_bins_),
      reflective_masks_(plane_ * mask_words_),
      missed_bins_(plane_, 0),
      hit_since_tick_(plane_, 0),
      reflective_bins_(plane_, 0),
      confirmed_ticks_(plane_, 0),
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
  const int tile_slots = window_.tileCells() * window_.tileCells();
  for (size_t i = 0; i < tiles.size(); ++i) {
    // The history is a summary of the active region only: it is not archived.
    if (!reflective_history_.empty() || !confirmed_history_.empty()) {
      const int first = static_cast<int>(window_.tileFirstSlot(tiles[i]));
      for (int slot = first; slot < first + tile_slots; ++slot) {
        reflective_history_.erase(slot);
        confirmed_history_.erase(slot);
      }
    }
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
  const uint64_t* mask = reflectiveMask(cell);
  int count = 0;
  for (int w = 0; w < mask_words_; ++w)
    count += __builtin_popcountll(mask[w]);
  return count;
}

double ReflectanceField::marginalOdds(const CellIndex& cell) const {
  return marginalOddsAt(window_.storageIndex(cell));
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
         missed_bins_.size() * sizeof(uint16_t) + hit_since_tick_.size() +
         reflective_bins_.size() * sizeof(uint16_t) + confirmed_ticks_.size() +
         tile_reflective_cells_.size() * sizeof(int) + tile_versions_.size() * sizeof(uint32_t) +
         historyBytes();
}

size_t ReflectanceField::historyBytes() const {
  // Per entry: the mask words, the history and key, a hash node and its bucket pointer.
  const size_t entry = mask_words_ * sizeof(uint64_t) + sizeof(CellHistory) + sizeof(int) +
                       2 * sizeof(void*) + sizeof(void*);
  const size_t confirmed_entry = mask_words_ * sizeof(uint64_t) + theta_bins_ * sizeof(int8_t) +
                                 sizeof(ConfirmedHistory) + sizeof(int) + 3 * sizeof(void*);
  return reflective_history_.size() * entry + confirmed_history_.size() * confirmed_entry;
}

int ReflectanceField::vacantTicksAt(int storage_index) const {
  const auto it = reflective_history_.find(storage_index);
  return it == reflective_history_.end() ? 0 : it->second.vacant_ticks;
}

int ReflectanceField::abandonedTicksAt(int storage_index) const {
  const auto it = confirmed_history_.find(storage_index);
  return it == confirmed_history_.end() ? 0 : it->second.abandoned_ticks;
}

int ReflectanceField::contradictedBinsAt(int storage_index) const {
  if (missed_bins_[storage_index] == 0) return 0;  // nothing seen through it
  const auto it = reflective_history_.find(storage_index);
  if (it == reflective_history_.end()) return 0;
  const int confidently_missed = log_odds_.minValue() / 2;
  int count = 0;
  forEachMaskBit(it->second.bins.data(), mask_words_, [&](int bin) {
    count += bins_[static_cast<size_t>(bin) * plane_ + storage_index] <= confidently_missed;
  });
  return count;
}

void ReflectanceField::clear() {
  reflective_history_.clear();
  confirmed_history_.clear();
  // Fresh zero pages instead of writing zeros over the old ones (100 MB for a batch's window, on
  // one thread): they fault in where the next insertions reach, on the inserting threads.
  bins_ = ZeroedHugeArray<int8_t>(bins_.size());
  reflective_masks_ = ZeroedHugeArray<uint64_t>(reflective_masks_.size());
  std::fill(missed_bins_.begin(), missed_bins_.end(), 0);
  std::fill(hit_since_tick_.begin(), hit_since_tick_.end(), 0);
  std::fill(reflective_bins_.begin(), reflective_bins_.end(), 0);
  std::fill(confirmed_ticks_.begin(), confirmed_ticks_.end(), 0);
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
  const size_t first = window_.tileFirstSlot(tile);
  for (size_t slot = first; slot < first + cells; ++slot) {
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
  std::fill_n(&hit_since_tick_[first], cells, 0);
  std::fill_n(&reflective_bins_[first], cells, 0);
  std::fill_n(&confirmed_ticks_[first], cells, 0);
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
    reflective_cells += reflective[c] != 0;
  }
  const int storage_tile = window_.storageTile(tile);
  tile_reflective_cells_[storage_tile] = reflective_cells;
  tick_pending_[storage_tile] = 1;
  ++tile_versions_[storage_tile];
}

void ReflectanceField::rebuildCellSummary(int storage_index) {
  uint64_t* mask = &reflective_masks_[static_cast<size_t>(storage_index) * mask_words_];
  std::fill(mask, mask + mask_words_, 0);
  uint16_t missed = 0, reflective = 0;
  for (int bin = 0; bin < theta_bins_; ++bin) {
    const int8_t v = bins_[bin * plane_ + storage_index];
    if (v > 0) mask[bin >> 6] |= uint64_t{1} << (bin & 63);
    reflective += v > 0;
    missed += v < 0;
  }
  missed_bins_[storage_index] = missed;
  const int tile = storage_index >> window_.tileSlotShift();
  tile_reflective_cells_[tile] += (reflective != 0) - (reflective_bins_[storage_index] != 0);
  reflective_bins_[storage_index] = reflective;
  tick_pending_[tile] = 1;
  ++tile_versions_[tile];
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

void ReflectanceField::tickPersistence(int remembered_min_bins, int confirmed_min_ticks,
                                       ParallelRunner* runner) {
  // On the runner's threads: they split the histories by hash bucket and the cells by tile, and
  // each updates only what it was given. Histories to drop or create change the maps, so the
  // threads collect those and the caller makes them after each step.
  const int threads = runner ? runner->threads() : 1;
  // Per thread: slots of histories to drop, of cells to get a history, of cells to become certain.
  std::vector<std::vector<int>> dropped(threads), remembered(threads), certain(threads);
  auto for_each_history = [&](auto& histories, auto&& update) {
    constexpr size_t kBucketsPerPart = 256;
    const size_t buckets = histories.bucket_count();
    parallelFor(runner, (buckets + kBucketsPerPart - 1) / kBucketsPerPart, 1,
                [&](size_t part, int thread) {
                  const size_t end = std::min(buckets, (part + 1) * kBucketsPerPart);
                  for (size_t b = part * kBucketsPerPart; b < end; ++b) {
                    for (auto it = histories.begin(b); it != histories.end(b); ++it)
                      update(it->first, it->second, thread);
                  }
                });
  };
  // Abandonment first, like vacancy: it compares with the last tick and reads the hits since.
  for_each_history(confirmed_history_, [&](int slot, ConfirmedHistory& history, int thread) {
    if (!reflective_bins_[slot]) {
      dropped[thread].push_back(slot);  // no longer confirmed
      return;
    }
    bool lost_certainty = false;
    forEachMaskBit(history.certain.data(), mask_words_, [&](int bin) {
      const int8_t value = bins_[static_cast<size_t>(bin) * plane_ + slot];
      lost_certainty |= value < history.at_tick[bin];
      history.at_tick[bin] = value;
    });
    if (hit_since_tick_[slot]) {
      history.abandoned_ticks = 0;
    } else if (lost_certainty && history.abandoned_ticks < 255) {
      ++history.abandoned_ticks;
    }
  });
  for (const std::vector<int>& part : dropped) {
    for (int slot : part)
      confirmed_history_.erase(slot);
  }
  // Vacancy first: it reads the hits since the last tick, which the loop below clears.
  for_each_history(reflective_history_, [&](int slot, CellHistory& history, int) {
    if (hit_since_tick_[slot]) {
      history.vacant_ticks = 0;
    } else if (missed_bins_[slot] > history.missed_at_tick && history.vacant_ticks < 255) {
      ++history.vacant_ticks;
    }
    history.missed_at_tick = missed_bins_[slot];
  });
  // Tile by tile: storage tiles are contiguous blocks of slots.
  const size_t tile_slots = size_t{1} << window_.tileSlotShift();
  constexpr size_t kTilesPerPart = 16;
  const size_t tiles = plane_ / tile_slots;
  parallelFor(runner, (tiles + kTilesPerPart - 1) / kTilesPerPart, 1, [&](size_t part, int thread) {
    const size_t end = std::min(plane_, (part + 1) * kTilesPerPart * tile_slots);
    for (size_t first = part * kTilesPerPart * tile_slots; first < end; first += tile_slots) {
      // A tile with no hit and no mask change since the last tick was left as this tick would
      // leave it: hit flags clear, unreflective cells at 0 ticks, reflective ones held, histories
      // holding their masks. Unless every cell is remembered, reflective or not (min bins 0).
      uint8_t& pending = tick_pending_[first >> window_.tileSlotShift()];
      if (!pending && remembered_min_bins > 0) continue;
      pending = 0;
      if (remembered_min_bins > 0 &&
          tile_reflective_cells_[first >> window_.tileSlotShift()] == 0) {
        // No cell of this tile is reflective: none is remembered or confirmed, so all that is
        // left to do is what the loop below does to unreflective cells.
        std::fill_n(&confirmed_ticks_[first], tile_slots, uint8_t{0});
        std::fill_n(&hit_since_tick_[first], tile_slots, uint8_t{0});
        continue;
      }
      for (size_t index = first; index < first + tile_slots; ++index) {
        if (reflective_bins_[index] >= remembered_min_bins) {
          const auto it = reflective_history_.find(static_cast<int>(index));
          if (it != reflective_history_.end()) {
            addReflectiveBins(index, it->second);
          } else {
            remembered[thread].push_back(static_cast<int>(index));
          }
        }
        uint8_t& ticks = confirmed_ticks_[index];
        if (!reflective_bins_[index]) {
          ticks = 0;
        } else if (hit_since_tick_[index] && ticks < 255) {
          ++ticks;  // not hit (occluded, out of view): held, neither confirmed nor reset
        }
        // Only hits make a bin certain.
        if (confirmed_min_ticks > 0 && ticks >= confirmed_min_ticks && hit_since_tick_[index]) {
          const auto it = confirmed_history_.find(static_cast<int>(index));
          if (it != confirmed_history_.end()) {
            addCertainBins(index, it->second);
          } else {
            certain[thread].push_back(static_cast<int>(index));
          }
        }
        hit_since_tick_[index] = 0;
      }
    }
  });
  for (const std::vector<int>& part : remembered) {
    for (int slot : part) {
      CellHistory& history = reflective_history_[slot];
      history.missed_at_tick = missed_bins_[slot];
      addReflectiveBins(slot, history);
    }
  }
  for (const std::vector<int>& part : certain) {
    for (int slot : part) {
      ConfirmedHistory& history = confirmed_history_[slot];
      history.certain.assign(mask_words_, 0);
      history.at_tick.resize(theta_bins_);
      addCertainBins(slot, history);
    }
  }
}

void ReflectanceField::addReflectiveBins(size_t storage_index, CellHistory& history) const {
  history.bins.resize(mask_words_, 0);
  const uint64_t* mask = &reflective_masks_[storage_index * mask_words_];
  for (int w = 0; w < mask_words_; ++w)
    history.bins[w] |= mask[w];
}

void ReflectanceField::addCertainBins(size_t storage_index, ConfirmedHistory& history) const {
  // Certain bins are reflective ones at the clamp.
  forEachMaskBit(&reflective_masks_[storage_index * mask_words_], mask_words_, [&](int bin) {
    const int8_t value = bins_[static_cast<size_t>(bin) * plane_ + storage_index];
    if (value < log_odds_.maxValue()) return;
    history.certain[bin >> 6] |= uint64_t{1} << (bin & 63);
    history.at_tick[bin] = value;
  });
}

void ReflectanceField::revertAt(int storage_index, int bin, int step) {
  // Clamping makes exact inversion impossible (a miss at the lower clamp changed nothing), so a
  // revert never moves a bin across the prior: it can under-correct, never invent.
  int8_t& v = bins_[static_cast<size_t>(bin) * plane_ + storage_index];
  const int shifted = std::clamp(v + step, log_odds_.minValue(), log_odds_.maxValue());
  // Never cross (or leave) the prior: that would turn "seen empty" into "seen reflective".
  const int updated = v < 0 ? std::min(shifted, 0) : (v > 0 ? std::max(shifted, 0) : 0);
  if (updated == v) return;
  v = static_cast<int8_t>(updated);
  rebuildCellSummary(storage_index);
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
