#include "reflectance_field_map/core/motion_removal.h"

#include <algorithm>
#include <cmath>

namespace rfm {

bool binIntervalsOverlap(int a, int a_len, int b, int b_len, int bins) {
  if (a_len >= bins || b_len >= bins) return a_len > 0 && b_len > 0;
  return positiveMod(b - a, bins) < a_len || positiveMod(a - b, bins) < b_len;
}

namespace {

// Appends the runs of contiguous reflective bins of one cell's mask.
template <typename Run>
void appendRuns(const uint64_t* mask, int bins, std::vector<Run>& runs) {
  const size_t first = runs.size();
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
    // Whole words of set bits at a time (bits past the last bin are never set).
    for (;;) {
      const int shift = bin & 63;
      const uint64_t rest = ~(mask[bin >> 6] >> shift);  // shifted-in zeros become ones
      const int ones = rest == 0 ? 64 : __builtin_ctzll(rest);
      if (ones < 64 - shift) {
        bin += ones;
        break;
      }
      bin += 64 - shift;
      if (bin >= bins) break;
    }
    runs.push_back({static_cast<int16_t>(start), static_cast<int16_t>(bin - start)});
  }
  // A run ending at the last bin continues into the one starting at bin 0.
  if (runs.size() - first >= 2 && runs[first].first_bin == 0 &&
      runs.back().first_bin + runs.back().length == bins) {
    runs.back().length = static_cast<int16_t>(runs.back().length + runs[first].length);
    runs.erase(runs.begin() + static_cast<std::ptrdiff_t>(first));
  }
}

CellBox bandBox(const CellBox& box, int first_row, int end_row) {
  return {{box.min.x(), box.min.y() + first_row}, {box.max.x(), box.min.y() + end_row}};
}

// Round columns (AnchorRules::column_max_radius_cells). Thinner things, such as table legs, are
// dots on the grid rather than rims, and rays pass beside them through their cells: drawn as
// structure they would cut those rays (Alg. 3).
constexpr double kColumnMinRadiusCells = 3.0;
// The directions turn through at least 45 deg around the rim. One direction along a straight
// stroke is a pane, or a person crossing the robot's view.
constexpr double kColumnMinTurn = kPi / 4.0;
// The cells lie on the rim, within a cell of it (cells filling a disc scatter by 0.35 of its
// radius about the fitted rim), and there are a few of them.
constexpr double kColumnMaxRmsCells = 1.0;
constexpr uint32_t kColumnMinRuns = 5;

// Gives a per-cell array `cells` entries, keeping its contents when it has them already.
template <typename T>
void keepCells(ZeroedHugeArray<T>& array, size_t cells) {
  if (array.size() != cells) array = ZeroedHugeArray<T>(cells, PageKind::kOrdinary);
}

}  // namespace

void MotionRemover::planTiles(const ReflectanceField& field, const CellBox& box) {
  const RollingWindow& window = field.window();
  tile_cells_ = window.tileCells();
  first_tile_ = window.tileOf(box.min);
  const TileIndex last = window.tileOf(box.max - CellIndex(1, 1));
  box_tiles_x_ = last.x() - first_tile_.x() + 1;
  tile_work_.assign(static_cast<size_t>(box_tiles_x_) * (last.y() - first_tile_.y() + 1),
                    TileWork::kComponents);
  const bool same_field = previous_field_ == field.identity();
  previous_versions_.resize(window.storageTiles());
  size_t i = 0;
  for (int ty = first_tile_.y(); ty <= last.y(); ++ty) {
    for (int tx = first_tile_.x(); tx <= last.x(); ++tx, ++i) {
      const TileIndex tile(tx, ty);
      const int storage_tile = window.storageTile(tile);
      // classify does not change the field: the version now is the one its result reflects.
      const uint32_t version = field.tileVersion(storage_tile);
      const bool unchanged = same_field && previous_versions_[storage_tile] == version;
      previous_versions_[storage_tile] = version;
      if (field.tileReflectiveCells(storage_tile) > 0) continue;
      const CellBox tile_box = window.tileBox(tile);
      const bool reuse = unchanged && box.contains(tile_box) && previous_box_.contains(tile_box);
      tile_work_[i] = reuse ? TileWork::kReuse : TileWork::kFreeSpace;
    }
  }
}

void MotionRemover::collectRuns(const ReflectanceField& field, const CellBox& box, const Band& band,
                                std::vector<Run>& runs) {
  const int bins = field.geometry().thetaBins();
  const size_t width = box.width();
  runs.clear();
  field.window().forEachTileSpan(
      bandBox(box, band.first_row, band.end_row), [&](int y, int x_begin, int x_end, int slot) {
        size_t local = (y - box.min.y()) * width + (x_begin - box.min.x());
        const TileWork work = tile_work_[boxTileOf(x_begin, y)];
        if (work != TileWork::kComponents) {
          // Band-relative run offsets for now.
          std::fill_n(&cell_first_run_[local], x_end - x_begin, static_cast<uint32_t>(runs.size()));
          return;
        }
        for (int x = x_begin; x < x_end; ++x, ++local, ++slot) {
          slots_[local] = slot;
          cell_first_run_[local] = static_cast<uint32_t>(runs.size());
          if (field.anyReflectiveAt(slot)) appendRuns(field.reflectiveMaskAt(slot), bins, runs);
        }
      });
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
  runs_in_[a] += runs_in_[b];
  solid_runs_[a] += solid_runs_[b];
  arrived_runs_[a] += arrived_runs_[b];
  departed_runs_[a] += departed_runs_[b];
  persistent_[a] |= persistent_[b];
  if (anchors_.tracksExtents()) {
    Extent& e = extent_[a];
    const Extent& f = extent_[b];
    e = {std::min(e.min_x, f.min_x), std::min(e.min_y, f.min_y), std::max(e.max_x, f.max_x),
         std::max(e.max_y, f.max_y)};
  }
  if (rank_[a] == rank_[b]) ++rank_[a];
}

bool MotionRemover::widelyVisible(const ReflectanceField& field, int slot,
                                  int reflective_bins) const {
  // Too few reflective bins cannot reach beta: the exact sum reads every bin.
  if (reflective_bins < min_widely_visible_bins_) return false;
  // Bounds from the reflective bins alone: unobserved bins add odds 1, missed bins between the
  // clamp's odds and those of one step below the prior. The exact sum when they do not decide.
  const LogOddsModel& model = field.logOdds();
  const int missed = field.missedBinsAt(slot);
  const int unobserved = field.geometry().thetaBins() - reflective_bins - missed;
  const double known = field.reflectiveOddsAt(slot) + unobserved;
  const double bin_width = field.geometry().binWidth();
  const double beta = rule_.options().beta;
  const double lowest =
      (known + missed * model.odds(static_cast<int8_t>(model.minValue()))) * bin_width;
  const double highest = (known + missed * model.odds(int8_t{-1})) * bin_width;
  if (lowest > beta * (1.0 + 1e-9)) return true;
  if (highest < beta * (1.0 - 1e-9)) return false;
  return field.marginalOddsAt(slot) > beta;
}

void MotionRemover::uniteNeighbour(size_t local, size_t n_local, int bins) {
  for (uint32_t r = cell_first_run_[local]; r < cell_first_run_[local + 1]; ++r) {
    // Dilate by one bin on each side: neighbouring bins are 26-connected.
    const int dilated_first = runs_[r].first_bin - 1;
    const int dilated_length = runs_[r].length + 2;
    for (uint32_t s = cell_first_run_[n_local]; s < cell_first_run_[n_local + 1]; ++s) {
      if (binIntervalsOverlap(dilated_first, dilated_length, runs_[s].first_bin, runs_[s].length,
                              bins)) {
        unite(r, s);
      }
    }
  }
}

void MotionRemover::joinBand(const ReflectanceField& field, const AnchorHistory& history,
                             const CellBox& box, const Band& band,
                             const std::function<CellClass(const CellIndex&)>& outside) {
  const int bins = field.geometry().thetaBins();
  const int width = box.width();
  // Forward neighbours only (each pair once); the row after the band belongs to the next band,
  // which joinRows connects afterwards.
  const CellIndex forward[4] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
  const CellIndex around[8] = {{1, 0}, {-1, 0}, {0, 1},  {0, -1},
                               {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
  const CellBox band_box = bandBox(box, band.first_row, band.end_row);
  field.window().forEachTileSpan(band_box, [&](int y, int x_begin, int x_end, int) {
    if (tile_work_[boxTileOf(x_begin, y)] != TileWork::kComponents) return;  // no runs
    size_t local = static_cast<size_t>(y - box.min.y()) * width + (x_begin - box.min.x());
    for (int x = x_begin; x < x_end; ++x, ++local) {
      const uint32_t first = cell_first_run_[local], last = cell_first_run_[local + 1];
      if (first == last) continue;
      const CellIndex cell(x, y);
      int reflective = 0;
      for (uint32_t r = first; r < last; ++r)
        reflective += runs_[r].length;
      const int slot = slots_[local];
      const CellAnchoring anchoring =
          anchors_.judge(field, history, slot, reflective, widelyVisible(field, slot, reflective));
      const bool anchor = anchoring.anchor, persistent = anchoring.persistent;
      anchor_cell_[local] = anchor;
      solid_[local] = anchoring.solid;
      for (uint32_t r = first; r < last; ++r) {
        const uint32_t root = find(r);
        ++runs_in_[root];
        solid_runs_[root] += anchoring.solid_anchor;
        arrived_runs_[root] += anchoring.arrived;
        departed_runs_[root] += anchoring.departed;
      }
      uint8_t seeded = anchoring.widely_visible ? kAnchoredFirmly
                       : anchor                 ? kAnchoredBySolidAngle
                                                : 0;
      // Long-confirmed cells anchor once their whole component is known (heldByPersistence).
      if (persistent) {
        for (uint32_t r = first; r < last; ++r)
          persistent_[find(r)] = 1;
      }
      // Known obstacles just outside the box seed components crossing its border.
      if (!seeded &&
          (x == box.min.x() || y == box.min.y() || x == box.max.x() - 1 || y == box.max.y() - 1)) {
        for (const CellIndex& d : around) {
          const CellIndex n = cell + d;
          if (box.contains(n)) continue;
          const CellClass c = outside(n);
          if (c == CellClass::kStatic || c == CellClass::kGlass || c == CellClass::kMetal) {
            seeded = kAnchoredFirmly;
            break;
          }
        }
      }
      if (seeded) {
        for (uint32_t r = first; r < last; ++r)
          anchored_[find(r)] |= seeded;
      }
      for (const CellIndex& d : forward) {
        const CellIndex n = cell + d;
        if (!band_box.contains(n)) continue;
        uniteNeighbour(
            local, static_cast<size_t>(n.y() - box.min.y()) * width + (n.x() - box.min.x()), bins);
      }
    }
  });
}

void MotionRemover::joinRows(const CellBox& box, int row, int bins) {
  const int width = box.width();
  const size_t row_start = static_cast<size_t>(row) * width;
  for (int x = 0; x < width; ++x) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (x + dx < 0 || x + dx >= width) continue;
      uniteNeighbour(row_start + x, row_start + width + x + dx, bins);
    }
  }
}

bool MotionRemover::spansAtLeast(uint32_t root, int min_cells) const {
  if (min_cells == 0) return true;
  const Extent& e = extent_[root];
  return std::max(e.max_x - e.min_x, e.max_y - e.min_y) + 1 >= min_cells;
}

bool MotionRemover::isStructure(uint32_t root) const {
  return (anchored_[root] & kAnchoredFirmly) ||
         ((anchored_[root] & kAnchoredBySolidAngle) && !departed(root)) ||
         heldByPersistence(root) ||
         (anchors_.solid_max_missed_ratio > 0.0 &&
          solid_runs_[root] >= anchors_.solid_min_share * runs_in_[root]);
}

void MotionRemover::anchorRoundColumns(const ReflectanceField& field, const CellBox& box) {
  const int bins = field.geometry().thetaBins();
  if (static_cast<int>(half_bin_cos_.size()) != 2 * bins) {
    half_bin_cos_.resize(2 * bins);
    half_bin_sin_.resize(2 * bins);
    for (int i = 0; i < 2 * bins; ++i) {
      const double angle = 0.5 * i * field.geometry().binWidth();
      half_bin_cos_[i] = std::cos(angle);
      half_bin_sin_[i] = std::sin(angle);
    }
  }
  // Each run of a component that is not yet structure is a point at its cell's centre
  // (box-local cells) seen along its central direction, weighted by its length in bins. Those
  // components are few (people, clutter): one fit each.
  constexpr uint32_t kNoFit = UINT32_MAX;
  column_fit_of_root_.assign(runs_.size(), kNoFit);
  column_fits_.clear();
  for (uint32_t r = 0; r < runs_.size(); ++r) {
    if (root_[r] == r && runs_in_[r] >= kColumnMinRuns && !isStructure(r)) {
      column_fit_of_root_[r] = static_cast<uint32_t>(column_fits_.size());
      column_fits_.push_back({r, NormalCircleFit()});
    }
  }
  if (column_fits_.empty()) return;
  const size_t width = box.width();
  field.window().forEachTileSpan(box, [&](int y, int x_begin, int x_end, int) {
    if (tile_work_[boxTileOf(x_begin, y)] != TileWork::kComponents) return;
    const size_t begin = (y - box.min.y()) * width + (x_begin - box.min.x());
    for (size_t local = begin; local < begin + (x_end - x_begin); ++local) {
      for (uint32_t r = cell_first_run_[local]; r < cell_first_run_[local + 1]; ++r) {
        const uint32_t fit = column_fit_of_root_[root_[r]];
        if (fit == kNoFit) continue;
        const int centre = (2 * runs_[r].first_bin + runs_[r].length) % (2 * bins);
        column_fits_[fit].second.add(static_cast<double>(local % width),
                                     static_cast<double>(y - box.min.y()), half_bin_cos_[centre],
                                     half_bin_sin_[centre], runs_[r].length);
      }
    }
  });
  const double min_spread = spreadOfTurn(kColumnMinTurn);
  for (const auto& [root, fit] : column_fits_) {
    if (fit.spread() < min_spread) continue;
    const NormalCircleFit::Circle circle = fit.fit();
    const bool column = circle.radius >= kColumnMinRadiusCells &&
                        circle.radius <= anchors_.column_max_radius_cells &&
                        circle.rms <= kColumnMaxRmsCells;
    if (column) anchored_[root] |= kAnchoredFirmly;
  }
}

bool MotionRemover::holdsSolidShare(const std::vector<uint32_t>& runs, uint32_t root) const {
  return runs[root] > 0 && runs[root] >= anchors_.solid_min_share * runs_in_[root];
}

bool MotionRemover::departed(uint32_t root) const {
  return holdsSolidShare(departed_runs_, root);
}

bool MotionRemover::arrived(uint32_t root) const {
  return holdsSolidShare(arrived_runs_, root);
}

CellClass MotionRemover::heldClass(const CellIndex& cell, int missed_bins) const {
  if (!previous_box_.contains(cell)) return CellClass::kUnknown;
  const uint32_t index = static_cast<uint32_t>(previous_box_.indexOf(cell));
  const auto it =
      std::lower_bound(drawn_.begin(), drawn_.end(), index,
                       [](const DrawnCell& drawn, uint32_t i) { return drawn.index < i; });
  if (it == drawn_.end() || it->index != index || missed_bins > it->missed_bins) {
    return CellClass::kUnknown;
  }
  return previous_classes_[index];
}

void MotionRemover::rememberDrawn(const ReflectanceField& field,
                                  const std::vector<CellClass>& classes) {
  drawn_.clear();
  for (size_t i = 0; i < classes.size(); ++i) {
    if (classes[i] == CellClass::kStatic || classes[i] == CellClass::kGlass ||
        classes[i] == CellClass::kMetal) {
      const int missed = std::min(field.missedBinsAt(slots_[i]), 0xffff);
      drawn_.push_back({static_cast<uint32_t>(i), static_cast<uint16_t>(missed)});
    }
  }
}

bool MotionRemover::anyArrived(uint32_t first, uint32_t last) const {
  for (uint32_t r = first; r < last; ++r) {
    if (arrived(root_[r])) return true;
  }
  return false;
}

bool MotionRemover::heldByPersistence(uint32_t root) const {
  // A person who walked in and stood still is confirmed for as long as they stand. A component
  // with as large a share of its runs in solid cells that arrived as makes one structure
  // (solid_min_share) arrived: its confirmed cells do not hold it.
  return persistent_[root] && !arrived(root) && spansAtLeast(root, anchors_.persistence_min_cells);
}

void MotionRemover::classifyBand(const ReflectanceField& field, const CellBox& box,
                                 const Band& band, std::vector<CellClass>& classes,
                                 MotionRemovalCounts& counts, std::vector<size_t>& glass) const {
  const size_t width = box.width();
  field.window().forEachTileSpan(
      bandBox(box, band.first_row, band.end_row), [&](int y, int x_begin, int x_end, int slot) {
        const size_t begin = (y - box.min.y()) * width + (x_begin - box.min.x());
        const size_t end = begin + (x_end - x_begin);
        switch (tile_work_[boxTileOf(x_begin, y)]) {
          case TileWork::kReuse: {
            const CellClass* previous =
                &previous_classes_[static_cast<size_t>(y - previous_box_.min.y()) *
                                       previous_box_.width() +
                                   (x_begin - previous_box_.min.x())];
            std::copy(previous, previous + (end - begin), &classes[begin]);
            counts.free_cells += std::count(previous, previous + (end - begin), CellClass::kFree);
            return;
          }
          case TileWork::kFreeSpace:
            for (size_t local = begin; local < end; ++local, ++slot) {
              classes[local] = rule_.classify(0, field.missedBinsAt(slot));
              counts.free_cells += classes[local] == CellClass::kFree;
            }
            return;
          case TileWork::kComponents:
            break;
        }
        for (size_t local = begin; local < end; ++local) {
          const uint32_t first = cell_first_run_[local], last = cell_first_run_[local + 1];
          int reflective = 0, widest = 0;
          bool anchored = false;
          for (uint32_t r = first; r < last; ++r) {
            reflective += runs_[r].length;
            widest = std::max<int>(widest, runs_[r].length);
            anchored |= isStructure(root_[r]);
          }
          CellClass& c = classes[local];
          c = rule_.classify(reflective, field.missedBinsAt(slots_[local]));
          if (c != CellClass::kOccupied) {
            counts.free_cells += c == CellClass::kFree;
          } else if (anchor_cell_[local] && anchored) {
            c = CellClass::kStatic;
            ++counts.static_cells;
          } else if (anchored && solid_[local]) {
            c = CellClass::kStatic;  // structure that is not seen through: no glass
            ++counts.static_cells;
          } else if (anchored) {
            c = rule_.isMetalLobe(widest) ? CellClass::kMetal : CellClass::kGlass;
            ++(c == CellClass::kMetal ? counts.metal_cells : counts.glass_cells);
            glass.push_back(local);
          } else if (const CellClass drawn = anyArrived(first, last)
                                                 ? CellClass::kMotion
                                                 : heldClass(box.cellAt(static_cast<int>(local)),
                                                             field.missedBinsAt(slots_[local]));
                     drawn == CellClass::kGlass || drawn == CellClass::kMetal) {
            c = drawn;  // still reflective, not seen through: structure as it was
            ++(c == CellClass::kMetal ? counts.metal_cells : counts.glass_cells);
            glass.push_back(local);
          } else if (drawn == CellClass::kStatic) {
            c = drawn;
            ++counts.static_cells;
          } else {
            c = CellClass::kMotion;
            ++counts.motion_cells;
          }
        }
      });
}

MotionRemovalCounts MotionRemover::classify(
    const ReflectanceField& field, const AnchorHistory& history, const CellBox& box,
    const std::function<CellClass(const CellIndex&)>& outside, std::vector<CellClass>& classes,
    ParallelRunner* runner) {
  const int bins = field.geometry().thetaBins();
  const size_t cells = static_cast<size_t>(box.width()) * box.height();
  // Bands of rows, a few per thread, handed out as threads become free: reflective cells
  // cluster, so equal bands are not equal work.
  const int threads = runner ? runner->threads() : 1;
  const int parts = std::max(1, std::min(threads == 1 ? 1 : 4 * threads, box.height()));
  std::vector<Band> bands(parts);
  for (int p = 0; p < parts; ++p)
    bands[p] = {box.height() * p / parts, box.height() * (p + 1) / parts};
  auto forEachBand = [&](const std::function<void(int)>& body) {
    parallelFor(runner, parts, 1, [&](size_t p, int) { body(static_cast<int>(p)); });
  };
  planTiles(field, box);
  // Runs per band, then one run list with global indices.
  keepCells(slots_, cells);
  cell_first_run_.assign(cells + 1, 0);
  band_runs_.resize(parts);
  forEachBand([&](int p) { collectRuns(field, box, bands[p], band_runs_[p]); });
  std::vector<uint32_t> band_offset(parts + 1, 0);
  for (int p = 0; p < parts; ++p)
    band_offset[p + 1] = band_offset[p] + static_cast<uint32_t>(band_runs_[p].size());
  runs_.resize(band_offset[parts]);
  cell_first_run_[cells] = band_offset[parts];
  min_widely_visible_bins_ = rule_.minWidelyVisibleBins(field.logOdds(), bins);
  parent_.resize(runs_.size());
  for (uint32_t i = 0; i < parent_.size(); ++i)
    parent_[i] = i;
  rank_.assign(runs_.size(), 0);
  anchored_.assign(runs_.size(), 0);
  persistent_.assign(runs_.size(), 0);
  runs_in_.assign(runs_.size(), 0);
  solid_runs_.assign(runs_.size(), 0);
  arrived_runs_.assign(runs_.size(), 0);
  departed_runs_.assign(runs_.size(), 0);
  extent_.resize(anchors_.tracksExtents() ? runs_.size() : 0);
  forEachBand([&](int p) {
    std::copy(band_runs_[p].begin(), band_runs_[p].end(), runs_.begin() + band_offset[p]);
    const size_t begin = static_cast<size_t>(bands[p].first_row) * box.width();
    const size_t end = static_cast<size_t>(bands[p].end_row) * box.width();
    const uint32_t offset = band_offset[p];
    for (size_t local = begin; local < end; ++local) {
      // Still band-relative here, this cell's and the next one's.
      const uint32_t first = cell_first_run_[local];
      const uint32_t last = local + 1 < end ? cell_first_run_[local + 1]
                                            : static_cast<uint32_t>(band_runs_[p].size());
      cell_first_run_[local] = first + offset;
      if (first == last || !anchors_.tracksExtents()) continue;
      const auto col = static_cast<int16_t>(local % box.width());
      const auto row = static_cast<int16_t>(local / box.width());
      for (uint32_t r = first + offset; r < last + offset; ++r)
        extent_[r] = {col, row, col, row};
    }
  });
  // Written by joinBand for every cell with runs before classifyBand reads them there.
  keepCells(anchor_cell_, cells);
  keepCells(solid_, cells);
  // Each band unites only its own runs, so bands do not touch each other's trees.
  forEachBand([&](int p) { joinBand(field, history, box, bands[p], outside); });
  for (int p = 0; p + 1 < parts; ++p) {
    if (bands[p].end_row > bands[p].first_row) joinRows(box, bands[p].end_row - 1, bins);
  }

  MotionRemovalCounts counts;
  root_.resize(runs_.size());
  for (uint32_t r = 0; r < runs_.size(); ++r) {
    root_[r] = find(r);
    counts.components += root_[r] == r;
  }
  if (anchors_.column_max_radius_cells > 0.0) anchorRoundColumns(field, box);
  classes.resize(cells);
  std::vector<MotionRemovalCounts> band_counts(parts);
  band_glass_.resize(parts);
  forEachBand([&](int p) {
    band_glass_[p].clear();
    classifyBand(field, box, bands[p], classes, band_counts[p], band_glass_[p]);
  });
  if (anchors_.glass_max_static_neighbours >= 0) {
    demoteGlassAgainstStructure(box, classes, band_counts.front());
  }
  previous_field_ = field.identity();
  previous_box_ = box;
  previous_classes_ = classes;
  rememberDrawn(field, classes);
  for (const MotionRemovalCounts& c : band_counts) {
    counts.static_cells += c.static_cells;
    counts.glass_cells += c.glass_cells;
    counts.metal_cells += c.metal_cells;
    counts.motion_cells += c.motion_cells;
    counts.free_cells += c.free_cells;
  }
  return counts;
}

// Glass is a thin surface with open space on both sides. A glassy cell lying against structure
// is that structure's surface, blurred (pose error, a rough wall): rays ending a cell deeper see
// through it near where it returns. Decided on the classes before any change, so demotions do
// not spread.
void MotionRemover::demoteGlassAgainstStructure(const CellBox& box, std::vector<CellClass>& classes,
                                                MotionRemovalCounts& counts) const {
  std::vector<size_t> demoted;
  const int width = box.width(), height = box.height();
  for (const std::vector<size_t>& glass : band_glass_) {
    for (size_t local : glass) {
      const int x = static_cast<int>(local % width), y = static_cast<int>(local / width);
      int neighbours = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx | dy) == 0 || x + dx < 0 || y + dy < 0 || x + dx >= width || y + dy >= height) {
            continue;
          }
          neighbours += classes[local + dy * width + dx] == CellClass::kStatic;
        }
      }
      if (neighbours > anchors_.glass_max_static_neighbours) demoted.push_back(local);
    }
  }
  for (size_t local : demoted) {
    --(classes[local] == CellClass::kMetal ? counts.metal_cells : counts.glass_cells);
    ++counts.static_cells;
    classes[local] = CellClass::kStatic;
  }
}

}  // namespace rfm
