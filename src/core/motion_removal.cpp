#include "reflectance_field_map/core/motion_removal.h"

#include <algorithm>

namespace rfm {

bool binIntervalsOverlap(int a, int a_len, int b, int b_len, int bins) {
  if (a_len >= bins || b_len >= bins) return a_len > 0 && b_len > 0;
  return positiveMod(b - a, bins) < a_len || positiveMod(a - b, bins) < b_len;
}

void MotionRemover::collectRuns(const ReflectanceField& field, const CellBox& box) {
  const int bins = field.geometry().thetaBins();
  runs_.clear();
  slots_.resize(static_cast<size_t>(box.width()) * box.height());
  cell_first_run_.assign(slots_.size() + 1, 0);
  size_t local = 0;
  field.window().forEachCell(box, [&](int, int, int slot) {
    slots_[local] = slot;
    cell_first_run_[local++] = static_cast<uint32_t>(runs_.size());
    if (!field.anyReflectiveAt(slot)) return;
    const uint64_t* mask = field.reflectiveMaskAt(slot);
    const size_t first = runs_.size();
    int bin = 0;
    while (bin < bins) {
      const uint64_t word = mask[bin >> 6] >> (bin & 63);
      if (word == 0) {  // skip to the next word
        bin = (bin | 63) + 1;
        continue;
      }
      bin += __builtin_ctzll(word);
      if (bin >= bins) break;
      const int start = bin;
      while (bin < bins && ((mask[bin >> 6] >> (bin & 63)) & 1u))
        ++bin;
      runs_.push_back({static_cast<int16_t>(start), static_cast<int16_t>(bin - start)});
    }
    // A run ending at the last bin continues into the one starting at bin 0.
    if (runs_.size() - first >= 2 && runs_[first].first_bin == 0 &&
        runs_.back().first_bin + runs_.back().length == bins) {
      runs_.back().length = static_cast<int16_t>(runs_.back().length + runs_[first].length);
      runs_.erase(runs_.begin() + static_cast<std::ptrdiff_t>(first));
    }
  });
  cell_first_run_[local] = static_cast<uint32_t>(runs_.size());
}

uint32_t MotionRemover::find(uint32_t node) {
  while (parent_[node] != node) {
    parent_[node] = parent_[parent_[node]];  // path halving
    node = parent_[node];
  }
  return node;
}

void MotionRemover::unite(uint32_t a, uint32_t b) {
  a = find(a);
  b = find(b);
  if (a == b) return;
  if (rank_[a] < rank_[b]) std::swap(a, b);
  parent_[b] = a;
  anchored_[a] |= anchored_[b];
  if (rank_[a] == rank_[b]) ++rank_[a];
}

bool MotionRemover::widelyVisible(const ReflectanceField& field, int slot,
                                  int reflective_bins) const {
  // Upper bound of eq. 7 from the bin counts first: the exact sum reads every bin.
  const LogOddsModel& model = field.logOdds();
  const int bins = field.geometry().thetaBins();
  const double bound = (reflective_bins * static_cast<double>(model.odds(model.maxValue())) +
                        (bins - reflective_bins)) *
                       field.geometry().binWidth();
  if (bound <= rule_.options().beta) return false;
  return field.marginalOddsAt(slot) > rule_.options().beta;
}

MotionRemovalCounts MotionRemover::classify(
    const ReflectanceField& field, const CellBox& box,
    const std::function<CellClass(const CellIndex&)>& outside, std::vector<CellClass>& classes) {
  const int bins = field.geometry().thetaBins();
  const int width = box.width();
  collectRuns(field, box);
  parent_.resize(runs_.size());
  for (uint32_t i = 0; i < parent_.size(); ++i)
    parent_[i] = i;
  rank_.assign(runs_.size(), 0);
  anchored_.assign(runs_.size(), 0);

  std::vector<uint8_t> widely_visible(static_cast<size_t>(width) * box.height(), 0);
  const CellIndex forward[4] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
  const CellIndex around[8] = {{1, 0}, {-1, 0}, {0, 1},  {0, -1},
                               {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
  size_t local = 0;
  for (int y = box.min.y(); y < box.max.y(); ++y) {
    for (int x = box.min.x(); x < box.max.x(); ++x, ++local) {
      const uint32_t first = cell_first_run_[local], last = cell_first_run_[local + 1];
      if (first == last) continue;
      const CellIndex cell(x, y);
      int reflective = 0;
      for (uint32_t r = first; r < last; ++r)
        reflective += runs_[r].length;
      const int slot = slots_[local];
      const bool anchor = widelyVisible(field, slot, reflective);
      widely_visible[local] = anchor;
      bool seeded =
          anchor || (persistence_ticks_ > 0 && field.confirmedTicksAt(slot) >= persistence_ticks_);
      // Known obstacles just outside the box seed components crossing its border.
      if (!seeded &&
          (x == box.min.x() || y == box.min.y() || x == box.max.x() - 1 || y == box.max.y() - 1)) {
        for (const CellIndex& d : around) {
          const CellIndex n = cell + d;
          if (box.contains(n)) continue;
          const CellClass c = outside(n);
          if (c == CellClass::kStatic || c == CellClass::kGlass || c == CellClass::kMetal) {
            seeded = true;
            break;
          }
        }
      }
      if (seeded) {
        for (uint32_t r = first; r < last; ++r)
          anchored_[find(r)] = 1;
      }
      for (const CellIndex& d : forward) {
        const CellIndex n = cell + d;
        if (!box.contains(n)) continue;
        const size_t n_local =
            static_cast<size_t>(n.y() - box.min.y()) * width + (n.x() - box.min.x());
        for (uint32_t r = first; r < last; ++r) {
          // Dilate by one bin on each side: neighbouring bins are 26-connected.
          const int dilated_first = runs_[r].first_bin - 1;
          const int dilated_length = runs_[r].length + 2;
          for (uint32_t s = cell_first_run_[n_local]; s < cell_first_run_[n_local + 1]; ++s) {
            if (binIntervalsOverlap(dilated_first, dilated_length, runs_[s].first_bin,
                                    runs_[s].length, bins)) {
              unite(r, s);
            }
          }
        }
      }
    }
  }

  MotionRemovalCounts counts;
  for (uint32_t r = 0; r < runs_.size(); ++r)
    counts.components += find(r) == r;
  classes.assign(static_cast<size_t>(width) * box.height(), CellClass::kUnknown);
  local = 0;
  for (int y = box.min.y(); y < box.max.y(); ++y) {
    for (int x = box.min.x(); x < box.max.x(); ++x, ++local) {
      const uint32_t first = cell_first_run_[local], last = cell_first_run_[local + 1];
      int reflective = 0, widest = 0;
      bool anchored = false;
      for (uint32_t r = first; r < last; ++r) {
        reflective += runs_[r].length;
        widest = std::max<int>(widest, runs_[r].length);
        anchored |= anchored_[find(r)] != 0;
      }
      CellClass& c = classes[local];
      if (!rule_.isOccupied(reflective)) {
        c = field.missedBinsAt(slots_[local]) > 0 ? CellClass::kFree : CellClass::kUnknown;
        counts.free_cells += c == CellClass::kFree;
      } else if (widely_visible[local]) {
        c = CellClass::kStatic;
        ++counts.static_cells;
      } else if (anchored) {
        c = rule_.isMetalLobe(widest) ? CellClass::kMetal : CellClass::kGlass;
        ++(c == CellClass::kMetal ? counts.metal_cells : counts.glass_cells);
      } else {
        c = CellClass::kMotion;
        ++counts.motion_cells;
      }
    }
  }
  return counts;
}

}  // namespace rfm
