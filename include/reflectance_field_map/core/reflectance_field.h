#pragma once

#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/log_odds.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/rolling_window.h"
#include "reflectance_field_map/core/tile_archive.h"
#include "reflectance_field_map/core/zeroed_huge_array.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <iosfwd>
#include <utility>
#include <vector>

namespace rfm {

namespace detail {
class SliceWriter;
}  // namespace detail

// Bit `bin` of a cell's reflective mask (ReflectanceField::reflectiveMaskAt): 64 bins a word.
inline bool maskBit(const uint64_t* mask, int bin) {
  return (mask[bin >> 6] >> (bin & 63)) & 1u;
}

// Whether a mask (of `bins` bins, or null: nothing reflective) has bit `bin` or a neighbour set:
// a wall grazed at a shallow angle is hit in neighbouring directions (the Alg. 3 check).
inline bool reflectiveNear(const uint64_t* mask, int bin, int bins) {
  return mask && (maskBit(mask, bin) || maskBit(mask, (bin + 1) % bins) ||
                  maskBit(mask, (bin + bins - 1) % bins));
}

// Whether a miss taking a bin from `old` (by `miss_step` < 0) makes it confidently missed: at or
// below `confident` (ReflectanceField::confidentMissValue) for the first time. One range test:
// the per-ray loop asks it of every miss.
inline bool becomesConfidentlyMissed(int old, int confident, int miss_step) {
  return static_cast<unsigned>(old - confident - 1) < static_cast<unsigned>(-miss_step);
}

// How many bits of a mask of `words` words are set.
inline int countMaskBits(const uint64_t* mask, int words) {
  int count = 0;
  for (int w = 0; w < words; ++w)
    count += __builtin_popcountll(mask[w]);
  return count;
}

// Calls visit(bin) for every set bit of a mask of `words` words, in increasing order.
template <typename Visit>
void forEachMaskBit(const uint64_t* mask, int words, Visit&& visit) {
  for (int w = 0; w < words; ++w) {
    for (uint64_t word = mask[w]; word != 0; word &= word - 1)
      visit(64 * w + __builtin_ctzll(word));
  }
}

// The Reflectance Field Map inside a robot-centred active region (paper Sec. III):
// one int8 log-odds Bayes filter per (x, y, theta) bin, stored bin-major ([bin][y][x]) in a
// rolling window of tiles so a ray, which updates a single theta slice, touches contiguous
// memory. Per cell it keeps which bins are reflective (p > 0.5, a bit mask) and how many are
// missed (p < 0.5), updated on every change, so eq. 5 and the component search never scan
// the bins. Tiles leaving the window are archived compressed and restored on return.
class ReflectanceField {
 public:
  // The window holds the active region, or `window_radius` (m) around its centre when larger.
  ReflectanceField(const GridOptions& grid, const LogOddsOptions& log_odds,
                   const ActiveRegionOptions& region, double window_radius = 0.0);

  const GridGeometry& geometry() const { return geometry_; }
  const LogOddsModel& logOdds() const { return log_odds_; }
  const RollingWindow& window() const { return window_; }
  CellBox activeBox() const { return window_.box(); }
  bool inActiveRegion(const CellIndex& cell) const { return window_.contains(cell); }

  // Scrolls the window by whole tiles so `robot_position`'s tile is central. Tiles that leave
  // are archived and cleared; tiles that enter are restored from the archive (tiles side by
  // side on the runner's threads, when given).
  WindowShift recenter(const Eigen::Vector2d& robot_position, ParallelRunner* runner = nullptr);
  // Whether recenter(robot_position) would move the window.
  bool wouldRecenter(const Eigen::Vector2d& robot_position) const {
    return !centred_ ||
           window_.originCentredOn(geometry_.cellOf(robot_position)) != window_.originTile();
  }

  // Bin access for cells inside the active region.
  int8_t value(const CellIndex& cell, int bin) const {
    return bins_[static_cast<size_t>(bin) * plane_ + window_.storageIndex(cell)];
  }
  void applyHit(const CellIndex& cell, int bin) { applyHitAt(window_.storageIndex(cell), bin); }
  void applyMiss(const CellIndex& cell, int bin) { applyMissAt(window_.storageIndex(cell), bin); }

  // A bin crossing the prior changes its cell's summaries (mask bit, reflective and missed
  // counts), which all bins of the cell share. Deferred, a mask bit's change is listed as this;
  // missed counts are summed (DeferredSummaries).
  struct SummaryChange {
    int32_t slot;
    int16_t bin;
    int8_t reflective;  // +1 became reflective, -1 stopped being
  };

  // Summary changes a writer deferred. Changes of a mask bit (and so of the reflective count) go
  // in lists by storage tile (tile & (parts - 1)): the lists touch disjoint cells and tiles, so
  // applySummaryChanges applies them side by side, each list in its order. Changes of the missed
  // count, most of all (a pass starts with every bin at the prior, so each (cell, bin) it misses
  // is one), are summed per cell instead: counts add up in any order.
  // The lists' headers live in the struct, in cache lines of its own: threads append side by side.
  struct alignas(64) DeferredSummaries {
    static constexpr int kMaxParts = 8;
    explicit DeferredSummaries(int parts = 1) : parts(parts) {}  // a power of two <= kMaxParts
    // Empties the lists. The sums are empty after every applySummaryChanges.
    void clear() {
      for (std::vector<SummaryChange>& list : lists)
        list.clear();
    }
    size_t size() const {
      size_t changes = 0;
      for (const std::vector<SummaryChange>& list : lists)
        changes += list.size();
      return changes;
    }
    int parts;
    std::array<std::vector<SummaryChange>, kMaxParts> lists;  // the first `parts` in use
    // By storage slot: the change of the cell's missed count, modulo 2^16 (a count, at most
    // 1440 bins, comes out right from any number of writers' sums).
    std::vector<uint16_t> missed;
    std::vector<uint8_t> touched;  // by storage tile: `missed` holds a change there
  };

  // Writes one theta slice (detail/slice_writer.h, where it is defined). With `deferred` set,
  // summary changes are appended there instead of applied.
  detail::SliceWriter sliceWriter(int bin, DeferredSummaries* deferred = nullptr);
  // Applies the writers' deferred changes, the lists of each part (and the sums of its tiles) on
  // one of the runner's threads when there are enough to share (all writers with the same number
  // of parts), and empties the writers' sums. Each bin must have had one writer, so that its
  // changes, which set and clear its mask bit, keep their order.
  void applySummaryChanges(std::vector<DeferredSummaries>& writers, ParallelRunner* runner);

  // Single updates by storage index = window().storageIndex(cell).
  void applyHitAt(int storage_index, int bin) {
    int8_t& v = bins_[static_cast<size_t>(bin) * plane_ + storage_index];
    const int8_t old = v;
    v = log_odds_.hit(old);
    hit_flags_[storage_index] = kHitSinceTick | kEverHit;
    tick_pending_[storage_index >> window_.tileSlotShift()] = 1;
    applySummaryChange(storage_index, bin, old <= 0 && v > 0, old < 0 && v >= 0 ? -1 : 0);
  }
  void applyMissAt(int storage_index, int bin) {
    int8_t& v = bins_[static_cast<size_t>(bin) * plane_ + storage_index];
    const int8_t old = v;
    v = log_odds_.miss(old);
    if (becomesConfidentlyMissed(old, confidentMissValue(), log_odds_.missStep())) {
      confident_miss_since_tick_[storage_index] = 1;
      tick_pending_[storage_index >> window_.tileSlotShift()] = 1;
    }
    applySummaryChange(storage_index, bin, old > 0 && v <= 0 ? -1 : 0, old >= 0 && v < 0);
  }
  // A bin at or below this value is missed with at least half the clamp's confidence.
  int confidentMissValue() const { return log_odds_.minValue() / 2; }

  // Inverse updates, to take back evidence found to come from beyond glass (online Alg. 3):
  // towards the prior, never past it.
  void revertHitAt(int storage_index, int bin) {
    revertAt(storage_index, bin, -log_odds_.hitStep());
  }
  void revertMissAt(int storage_index, int bin) {
    revertAt(storage_index, bin, -log_odds_.missStep());
  }

  // Per-cell summaries (cell inside the active region).
  int maskWords() const { return mask_words_; }
  const uint64_t* reflectiveMask(const CellIndex& cell) const {
    return &reflective_masks_[static_cast<size_t>(window_.storageIndex(cell)) * mask_words_];
  }
  // How many bins of the cell are reflective (kept with the masks, so scans over the region skip
  // empty cells and count bins without reading the masks).
  int reflectiveBinsAt(int storage_index) const { return reflective_bins_[storage_index]; }
  bool anyReflectiveAt(int storage_index) const { return reflective_bins_[storage_index] != 0; }
  const uint64_t* reflectiveMaskAt(int storage_index) const {
    return &reflective_masks_[static_cast<size_t>(storage_index) * mask_words_];
  }
  int missedBinsAt(int storage_index) const { return missed_bins_[storage_index]; }
  // Whether the cell reflects in some direction within `max_off` (rad) of `axis` (unit), either
  // way along it.
  bool reflectsNearAxisAt(int storage_index, const Eigen::Vector2d& axis, double max_off) const;
  double marginalOddsAt(int storage_index) const;
  // The part of marginalOddsAt's sum (without the bin width) from the reflective bins alone.
  double reflectiveOddsAt(int storage_index) const;
  int reflectiveBins(const CellIndex& cell) const;
  int missedBins(const CellIndex& cell) const { return missed_bins_[window_.storageIndex(cell)]; }
  bool isReflectiveAt(int storage_index, int bin) const {
    return maskBit(reflectiveMaskAt(storage_index), bin);
  }
  bool isReflective(const CellIndex& cell, int bin) const {
    return maskBit(reflectiveMask(cell), bin);
  }
  int8_t valueAt(int storage_index, int bin) const {
    return bins_[static_cast<size_t>(bin) * plane_ + storage_index];
  }

  // What changed since the last persistence tick, for the anchor history (AnchorHistory::tick
  // reads and clears it): the cells hit, the cells with a bin newly missed with confidence
  // (confidentMissValue), and the storage tiles where either happened or a mask changed. A tick
  // changes nothing in the other tiles.
  bool hitSinceTick(int storage_index) const {
    return (hit_flags_[storage_index] & kHitSinceTick) != 0;
  }
  bool confidentlyMissedSinceTick(int storage_index) const {
    return confident_miss_since_tick_[storage_index] != 0;
  }
  void clearSinceTick(int first_slot, int count) {
    uint8_t* const flags = &hit_flags_[first_slot];
    for (int i = 0; i < count; ++i)
      flags[i] &= kEverHit;  // a tick forgets what happened since the last one, not the hits
    std::fill_n(&confident_miss_since_tick_[first_slot], count, uint8_t{0});
  }
  // Whether a beam has ended in the cell since the field was cleared (or the cell's tile entered
  // the window: a restored tile remembers the hits of its reflective cells only). Glass away
  // from its normal still returns now and then (a weak echo, dirt); an opening only where
  // something passes through it.
  bool everHitAt(int storage_index) const { return (hit_flags_[storage_index] & kEverHit) != 0; }
  // Whether the storage tile changed since the last tick; from now on it has not.
  bool takeTickPending(int storage_tile) {
    return std::exchange(tick_pending_[storage_tile], uint8_t{0}) != 0;
  }

  // Per storage tile (window().tileSlotShift()): how many cells have a reflective bin, and a
  // version that changes whenever a cell summary of the tile (mask, reflective or missed count)
  // changes or the tile is cleared. Motion removal reuses what it found for tiles that did not
  // change since its last run. `identity()` tells fields apart (no two share one).
  int tileReflectiveCells(int storage_tile) const { return tile_reflective_cells_[storage_tile]; }
  uint32_t tileVersion(int storage_tile) const { return tile_versions_[storage_tile]; }
  uint64_t identity() const { return identity_.value; }

  // eq. 7: sum over theta of the odds of reflectance times the bin width (rad).
  double marginalOdds(const CellIndex& cell) const;

  // Memory.
  size_t activeBytes() const;
  // The pages of the slices and masks: huge unless the window is large (offline, a campus).
  PageKind pages() const { return bins_.pages(); }
  size_t archivedBytes() const { return archive_.bytes(); }
  size_t archivedTiles() const { return archive_.tileCount(); }
  const TileArchive& archive() const { return archive_; }

  // Forgets everything (active and archived). Huge pages are zeroed in place where evidence
  // was; ordinary pages (a large window) are replaced by fresh ones. Either way pages no ray
  // reached stay unmapped until insertions reach them, unless prefault() brings them in.
  void clear();
  // Faults the slices' and masks' pages in now (a live mapper: its first scans must not wait
  // for them).
  void prefault() {
    bins_.prefault();
    reflective_masks_.prefault();
    missed_bins_.prefault();
    hit_flags_.prefault();
    confident_miss_since_tick_.prefault();
    reflective_bins_.prefault();
  }

  // Binary state (window origin, active bins, archive) for save/load.
  void write(std::ostream& out) const;
  bool read(std::istream& in);

 private:
  friend class detail::SliceWriter;
  static constexpr uint8_t kHitSinceTick = 1, kEverHit = 2;  // bits of hit_flags_
  void applySummaryChange(int storage_index, int bin, int reflective, int missed) {
    if ((reflective | missed) == 0) return;
    const int tile = storage_index >> window_.tileSlotShift();
    if (reflective != 0) {
      tick_pending_[tile] = 1;
      uint64_t& word =
          reflective_masks_[static_cast<size_t>(storage_index) * mask_words_ + (bin >> 6)];
      const uint64_t bit = uint64_t{1} << (bin & 63);
      word = reflective > 0 ? (word | bit) : (word & ~bit);
      uint16_t& count = reflective_bins_[storage_index];
      const bool was_reflective = count != 0;
      count = static_cast<uint16_t>(count + reflective);
      tile_reflective_cells_[tile] += (count != 0) - was_reflective;
    }
    missed_bins_[storage_index] += missed;
    ++tile_versions_[tile];
  }
  void revertAt(int storage_index, int bin, int step);
  void archiveTiles(const std::vector<TileIndex>& tiles, ParallelRunner* runner);
  void restoreTiles(const std::vector<TileIndex>& tiles, ParallelRunner* runner);
  bool tileHoldsEvidence(const TileIndex& tile) const;
  // Whether any of the `count` storage slots from `first` holds a bin off the prior.
  bool slotsHoldEvidence(size_t first, size_t count) const;
  // Clears the tile's cell summaries, and its bins too unless they are known to be clear.
  void clearTileStorage(const TileIndex& tile, bool bins_too);
  // Recomputes the summaries of a tile just restored into storage (cleared before).
  void rebuildSummaries(const TileIndex& tile);
  void gatherTile(const TileIndex& tile, std::vector<int8_t>& bins) const;
  void scatterTile(const TileIndex& tile, const std::vector<int8_t>& bins);

  GridGeometry geometry_;
  LogOddsModel log_odds_;
  RollingWindow window_;
  int theta_bins_;
  size_t plane_;  // cells in one theta slice of the window
  int mask_words_;
  bool centred_ = false;
  ZeroedHugeArray<int8_t> bins_;                // [bin][y][x]
  ZeroedHugeArray<uint64_t> reflective_masks_;  // [y][x][word]
  // The cell summaries, zero where no ray has been: on a large window untouched pages stay
  // unmapped, as the slices' do.
  ZeroedHugeArray<uint16_t> missed_bins_;               // [y][x]
  ZeroedHugeArray<uint8_t> hit_flags_;                  // [y][x], kHitSinceTick | kEverHit
  ZeroedHugeArray<uint8_t> confident_miss_since_tick_;  // [y][x]
  ZeroedHugeArray<uint16_t> reflective_bins_;           // [y][x]
  std::vector<int> tile_reflective_cells_;              // per storage tile
  std::vector<uint32_t> tile_versions_;                 // per storage tile
  // Per storage tile: a cell was hit, a bin became confidently missed, or a mask changed since
  // the last persistence tick. A tick changes nothing in the other tiles (AnchorHistory::tick).
  std::vector<uint8_t> tick_pending_;
  // A new number for every field object, copies and assignments included.
  struct Identity {
    Identity();
    Identity(const Identity&) : Identity() {}
    Identity& operator=(const Identity&) {
      value = Identity().value;
      return *this;
    }
    uint64_t value;
  };
  Identity identity_;
  TileArchive archive_;
};

// Tiles per side of the active window: the radius must stay inside the window while the robot
// is anywhere within the centre tile.
int activeWindowTiles(double radius, double resolution, int tile_cells);

}  // namespace rfm
