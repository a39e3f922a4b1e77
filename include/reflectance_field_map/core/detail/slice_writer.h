// The writer of one theta slice of the field, which the inserter's hot loop runs.
#pragma once

#include "reflectance_field_map/core/detail/compiler.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <cstdint>
#include <vector>

namespace rfm {
namespace detail {

// Writes one theta slice with everything it needs held locally: int8 stores may alias any
// member, so going through `this` would reload them after every update.
// Writers of different slices may run concurrently when each defers its summary changes to
// its own lists, applied afterwards by ReflectanceField::applySummaryChanges.
class SliceWriter {
 public:
  RFM_ALWAYS_INLINE void hit(int slot) {
    int8_t& v = bins_[slot];
    const int old = v;
    const int updated = old + hit_step_ > max_ ? max_ : old + hit_step_;
    v = static_cast<int8_t>(updated);
    // Every writer stores the same flags: relaxed atomic, so concurrent writers are well defined.
    constexpr uint8_t kHitFlags = ReflectanceField::kHitSinceTick | ReflectanceField::kEverHit;
    if (relaxedLoad(&hit_flags_[slot]) != kHitFlags) {
      relaxedStore(&hit_flags_[slot], kHitFlags);
      relaxedStore(&tick_pending_[slot >> tile_slot_shift_], 1);
    }
    // Only a bin in [-hit_step, 0] reaches or crosses the prior (p = 0.5) on a hit: one test.
    if (static_cast<unsigned>(old + hit_step_) <= static_cast<unsigned>(hit_step_)) {
      change(slot, old <= 0 && updated > 0, old < 0 && updated >= 0 ? -1 : 0);
    }
  }
  RFM_ALWAYS_INLINE void miss(int slot) {
    int8_t& v = bins_[slot];
    const int old = v;
    // Most misses fall on free space already at the floor: nothing changes, nothing to store.
    if (old <= min_) return;
    const int updated = old + miss_step_ < min_ ? min_ : old + miss_step_;
    // A bin becoming confidently missed: the cell may now be seen free (AnchorHistory::tick).
    // Tested before the store, which may alias the members.
    const bool newly_confident = becomesConfidentlyMissed(old, confident_miss_, miss_step_);
    v = static_cast<int8_t>(updated);
    // Stored once per cell and tick: the tile's flag is shared with the other writers' threads.
    if (newly_confident && !relaxedLoad(&confident_miss_flags_[slot])) {
      relaxedStore(&confident_miss_flags_[slot], 1);
      relaxedStore(&tick_pending_[slot >> tile_slot_shift_], 1);
    }
    // Only a bin in [0, -miss_step] reaches or crosses the prior on a miss: one test.
    if (static_cast<unsigned>(old) <= static_cast<unsigned>(-miss_step_)) {
      change(slot, old > 0 && updated <= 0 ? -1 : 0, old >= 0 && updated < 0);
    }
  }

 private:
  friend class rfm::ReflectanceField;
  // Called only for a change: every value in the ranges tested above crosses or reaches 0.
  // Inlined: left to itself the compiler called it through the PLT, 5 % of a pass's instructions.
  RFM_ALWAYS_INLINE void change(int slot, int reflective, int missed) {
    if (deferred_) {
      if (missed != 0) {
        missed_sums_[slot] += static_cast<uint16_t>(missed);
        touched_tiles_[slot >> tile_slot_shift_] = 1;
      }
      if (reflective != 0) {
        deferred_[(slot >> tile_slot_shift_) & part_mask_].push_back(
            {slot, static_cast<int16_t>(bin_), static_cast<int8_t>(reflective)});
      }
    } else {
      field_->applySummaryChange(slot, bin_, reflective, missed);
    }
  }
  int8_t* bins_;
  uint8_t* hit_flags_;
  uint8_t* confident_miss_flags_;
  uint8_t* tick_pending_;
  ReflectanceField* field_;
  std::vector<ReflectanceField::SummaryChange>* deferred_;  // DeferredSummaries::lists, or null
  uint16_t* missed_sums_;   // DeferredSummaries::missed, when deferred_ is set
  uint8_t* touched_tiles_;  // DeferredSummaries::touched, when deferred_ is set
  int tile_slot_shift_, part_mask_;
  int bin_, hit_step_, miss_step_, min_, max_, confident_miss_;
};

}  // namespace detail

inline detail::SliceWriter ReflectanceField::sliceWriter(int bin, DeferredSummaries* deferred) {
  detail::SliceWriter w;
  w.bins_ = &bins_[static_cast<size_t>(bin) * plane_];
  w.hit_flags_ = hit_flags_.data();
  w.confident_miss_flags_ = confident_miss_since_tick_.data();
  w.tick_pending_ = tick_pending_.data();
  w.field_ = this;
  w.deferred_ = deferred ? deferred->lists.data() : nullptr;
  w.missed_sums_ = nullptr;
  w.touched_tiles_ = nullptr;
  if (deferred) {
    if (deferred->missed.size() != plane_) {
      deferred->missed.assign(plane_, 0);
      deferred->touched.assign(window_.storageTiles(), 0);
    }
    w.missed_sums_ = deferred->missed.data();
    w.touched_tiles_ = deferred->touched.data();
  }
  w.tile_slot_shift_ = window_.tileSlotShift();
  w.part_mask_ = deferred ? deferred->parts - 1 : 0;
  w.bin_ = bin;
  w.hit_step_ = log_odds_.hitStep();
  w.miss_step_ = log_odds_.missStep();
  w.min_ = log_odds_.minValue();
  w.max_ = log_odds_.maxValue();
  w.confident_miss_ = confidentMissValue();
  return w;
}

}  // namespace rfm
