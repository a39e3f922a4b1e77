#pragma once

#include "reflectance_field_map/core/detail/compiler.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/rolling_window.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

namespace rfm {

// Neighbouring beams of a scan cross mostly the same cells: 0.25 deg apart, they are less than
// a 5 cm cell apart for the first 11 m, so walking each ray on its own visits a cell of a
// theta bin's fan about three times. Sweeping the fan column by column along its major axis
// visits the union of its rays' cells, mostly once each.
namespace detail {

constexpr int kMaxFanRays = 32;

// Whether a visitor offers once(slot), for visits the sweep knows to be the only visit of a
// cell that is no ray's end cell (see visitCellsOfRays).
template <typename Visit, typename = void>
struct HasOnce : std::false_type {};
template <typename Visit>
struct HasOnce<Visit, std::void_t<decltype(std::declval<Visit&>().once(0))>> : std::true_type {};

constexpr int kFractionBits = 32;
constexpr int64_t kOneCell = int64_t{1} << kFractionBits;

inline int64_t toFixed(double value) {
  const double scaled = value * static_cast<double>(kOneCell);
  return static_cast<int64_t>(scaled + (scaled >= 0.0 ? 0.5 : -0.5));
}

// A ray in its fan's axes (major: the axis it advances along fastest). Minor coordinates are
// fixed point with 32 fraction bits, in cells: a row is a shift, a column an add. No
// initialisers: a fan is set up per theta bin and scan.
struct FanRay {
  int64_t first_exit;  // minor coordinate where the ray crosses the first column's far edge
  int64_t per_column;  // its change from one column edge to the next
  // On an exact corner the traversal steps along y first: with x major the row beyond the
  // corner still belongs to the column, with y major it belongs to the next. 1 when a
  // coordinate on a row edge counts in the row below, else 0.
  int64_t tie_bias;
  int columns;  // columns after the first
  int end_row;
  int row_low, row_high;  // rows between the start and end cells
};

// Minor coordinate where the ray crosses the far edge of column i, tie bias applied, unclamped:
// exitRow is its floor, clamped to the ray's rows.
inline int64_t rawExit(const FanRay& ray, int column) {
  return ray.first_exit + column * ray.per_column - ray.tie_bias;
}

// A visit to a cell of the joined columns: once(slot) where the sweep knows it is the cell's only
// visit (see visitCellsOfRays), else the visitor's stamped visit.
template <bool kJoinedOnce, typename Visit>
RFM_ALWAYS_INLINE inline void visitJoinedCell(Visit& visit, int slot) {
  if constexpr (kJoinedOnce) {
    visit.once(slot);
  } else {
    visit(slot);
  }
}

// Row in which the ray leaves column i < columns.
inline int exitRow(const FanRay& ray, int column) {
  const int row = static_cast<int>(rawExit(ray, column) >> kFractionBits);  // arithmetic: floor
  return std::min(std::max(row, ray.row_low), ray.row_high);
}

// Number of columns, from the first, over which two neighbouring rays cross every column edge
// less than a row apart (with a margin for rounding): their rows then differ by at most one.
inline int columnsJoined(const FanRay& a, const FanRay& b) {
  constexpr int64_t kLimit = kOneCell - (int64_t{1} << 16);
  const int64_t apart = std::abs(a.first_exit - b.first_exit);
  const int64_t spread = std::abs(a.per_column - b.per_column);
  if (apart >= kLimit) return 0;
  if (spread == 0) return std::numeric_limits<int>::max();
  return static_cast<int>(
      std::min<int64_t>((kLimit - 1 - apart) / spread + 1, std::numeric_limits<int>::max()));
}

// Joined columns [begin, end) (begin > 0) in a simpler form, where it holds: every column's run
// is rows [low >> kFractionBits, high >> kFractionBits], low and high growing by their steps from
// column to column.
struct JoinedRun {
  int64_t low, low_step, high, high_step;
};

// Whether the joined columns [begin, end) of the outer rays `a` and `b` take that form: where
// neither ray's rows are clamped (exitRow) and one ray stays on the same side of the other.
// Both hold throughout when they hold at the first entry edge and the last exit edge: the raw
// rows and their difference are linear in the column. A run's lowest row is then the lower
// ray's entry or exit row, whichever its slope makes lower, and its highest the upper ray's.
inline bool joinedRun(const FanRay& a, const FanRay& b, int begin, int end, JoinedRun& run) {
  auto unclamped = [](const FanRay& ray, int64_t raw) {
    const int row = static_cast<int>(raw >> kFractionBits);
    return row >= ray.row_low && row <= ray.row_high;
  };
  const int64_t a_entry = rawExit(a, begin - 1), a_exit = rawExit(a, end - 1);
  const int64_t b_entry = rawExit(b, begin - 1), b_exit = rawExit(b, end - 1);
  if (!unclamped(a, a_entry) || !unclamped(a, a_exit) || !unclamped(b, b_entry) ||
      !unclamped(b, b_exit)) {
    return false;
  }
  const FanRay* lower;
  const FanRay* upper;
  if (a_entry <= b_entry && a_exit <= b_exit) {
    lower = &a;
    upper = &b;
  } else if (b_entry <= a_entry && b_exit <= a_exit) {
    lower = &b;
    upper = &a;
  } else {
    return false;
  }
  // Rows only rise along a ray whose step is positive: its entry row is its lowest in a column.
  run.low = rawExit(*lower, lower->per_column >= 0 ? begin - 1 : begin);
  run.low_step = lower->per_column;
  run.high = rawExit(*upper, upper->per_column >= 0 ? begin : begin - 1);
  run.high_step = upper->per_column;
  return true;
}

// The joined columns of a JoinedRun: columns[0], columns[step], ... (`count` of them) of the
// column offsets, rows[row] the row offsets.
template <bool kJoinedOnce, typename Visit>
RFM_ALWAYS_INLINE inline void sweepJoinedRun(const int* columns, int step, int count,
                                             const int* rows, JoinedRun run, Visit& visit) {
  for (; count > 0; --count, columns += step) {
    const int column_offset = *columns;
    const int* const run_end = rows + (run.high >> kFractionBits);
    for (const int* row = rows + (run.low >> kFractionBits); row <= run_end; ++row)
      visitJoinedCell<kJoinedOnce>(visit, column_offset + *row);
    run.low += run.low_step;
    run.high += run.high_step;
  }
}

// Always inlined: the caller's visitor then stays a local that no pointer reaches, so its state
// lives in registers even though a visitor's byte stores may alias any memory.
template <int kMajor, bool kJoinedOnce, typename Visit>
RFM_ALWAYS_INLINE inline void sweepFan(int column0, int row0, int step, FanRay* fan, int count,
                                       const RollingWindow& window, Visit& visit) {
  // Rays lie inside the window, where the offset tables wrap rows and columns around storage.
  const int* const column_offsets = kMajor == 0 ? window.columnOffsets() : window.rowOffsets();
  const int* const row_offsets = kMajor == 0 ? window.rowOffsets() : window.columnOffsets();
  const CellIndex& offset_origin = window.offsetOrigin();
  const int row_shift = -offset_origin[1 - kMajor];    // cell row -> index of row_offsets
  int column_index = column0 - offset_origin[kMajor];  // index of column_offsets
  auto visit_rows = [&](int low, int high) RFM_ALWAYS_INLINE {
    const int column_offset = column_offsets[column_index];
    for (int r = low + row_shift; r <= high + row_shift; ++r)
      visit(column_offset + row_offsets[r]);
  };
  // The joined columns' runs: each cell once, and no ray ends there. A loop of its own: folded
  // into visit_rows behind a flag, the sweep ran slower (paired ratio 1.24 -> 1.31).
  auto visit_joined_rows = [&](int low, int high) RFM_ALWAYS_INLINE {
    const int column_offset = column_offsets[column_index];
    for (int r = low + row_shift; r <= high + row_shift; ++r)
      visitJoinedCell<kJoinedOnce>(visit, column_offset + row_offsets[r]);
  };
  auto next_column = [&] { column_index += step; };
  auto entry_row = [row0](const FanRay& ray, int column) {
    return column == 0 ? row0 : exitRow(ray, column - 1);
  };

  int active[kMaxFanRays];  // rays not yet ended, in fan order
  int active_count = count;
  for (int k = 0; k < count; ++k)
    active[k] = k;
  bool drifted_apart = false;  // for good: gaps only grow along the fan
  // joined_with_previous[a]: columnsJoined of active rays a - 1 and a (a > 0). Computed when two
  // rays become neighbours, not again every time a ray ends: it costs a division.
  int joined_with_previous[kMaxFanRays];
  for (int a = 1; a < active_count; ++a)
    joined_with_previous[a] = columnsJoined(fan[active[a - 1]], fan[active[a]]);
  int column = 0;
  while (active_count > 0) {
    if (drifted_apart) {
      // Neighbours now cross column edges rows apart and share few cells: each ray walks its
      // own columns to its end, with no runs to merge (a cell two rays share is visited twice).
      for (int a = 0; a < active_count; ++a) {
        const FanRay& ray = fan[active[a]];
        int entry = entry_row(ray, column);
        for (int c = column, index = column_index; c <= ray.columns; ++c, index += step) {
          const int exit = c == ray.columns ? ray.end_row : exitRow(ray, c);
          const int column_offset = column_offsets[index];
          const int high = std::max(entry, exit) + row_shift;
          for (int r = std::min(entry, exit) + row_shift; r <= high; ++r)
            visit(column_offset + row_offsets[r]);
          entry = exit;
        }
      }
      return;
    }
    // Until a ray ends or neighbours drift apart, the rays' cells in a column form one run,
    // bounded by the outermost two rays (slopes are monotone along the fan).
    int first_end = std::numeric_limits<int>::max(), joined = first_end;
    for (int a = 0; a < active_count; ++a) {
      first_end = std::min(first_end, fan[active[a]].columns);
      if (a > 0) joined = std::min(joined, joined_with_previous[a]);
    }
    drifted_apart = joined < first_end;
    const int joined_end = std::max(column, std::min(first_end, joined));
    if (column < joined_end) {
      const FanRay& first = fan[active[0]];
      const FanRay& last = fan[active[active_count - 1]];
      int first_row = entry_row(first, column), last_row = entry_row(last, column);
      auto visit_joined_column = [&]() RFM_ALWAYS_INLINE {
        const int first_exit = exitRow(first, column), last_exit = exitRow(last, column);
        visit_joined_rows(std::min(std::min(first_row, first_exit), std::min(last_row, last_exit)),
                          std::max(std::max(first_row, first_exit), std::max(last_row, last_exit)));
        first_row = first_exit;
        last_row = last_exit;
        next_column();
        ++column;
      };
      // The first column's entry is the origin's row, not a column edge.
      if (column == 0) visit_joined_column();
      JoinedRun run;
      if (column < joined_end && joinedRun(first, last, column, joined_end, run)) {
        const int* const columns = &column_offsets[column_index];
        const int* const rows = row_offsets + row_shift;
        const int count = joined_end - column;
        sweepJoinedRun<kJoinedOnce>(columns, step, count, rows, run, visit);
        column_index += step * count;
        column = joined_end;
      }
      while (column < joined_end)
        visit_joined_column();
    }
    if (drifted_apart) continue;  // the rays walk alone from here
    // One column ray by ray (a ray ends in it): each ray's rows, merged into runs as they come.
    int run_low = 0, run_high = -1;  // empty
    int still_active = 0;
    for (int a = 0; a < active_count; ++a) {
      const FanRay& ray = fan[active[a]];
      const int entry = entry_row(ray, column);
      const int exit = ray.columns == column ? ray.end_row : exitRow(ray, column);
      const int low = std::min(entry, exit), high = std::max(entry, exit);
      if (run_low <= run_high && low <= run_high + 1 && high >= run_low - 1) {
        run_low = std::min(run_low, low);
        run_high = std::max(run_high, high);
      } else {
        if (run_low <= run_high) visit_rows(run_low, run_high);
        run_low = low;
        run_high = high;
      }
      if (ray.columns > column) {
        if (still_active > 0) {
          // Neighbours as before, or new ones where the rays between them ended.
          joined_with_previous[still_active] =
              still_active == a ? joined_with_previous[a]
                                : columnsJoined(fan[active[still_active - 1]], ray);
        }
        active[still_active++] = active[a];
      }
    }
    if (run_low <= run_high) visit_rows(run_low, run_high);
    active_count = still_active;
    ++column;
    next_column();
  }
}

}  // namespace detail

// Visits every cell that walkWindowCells visits for each of the rays rays[order[k]],
// k in [0, count), end cells included, in no particular order; a cell may be visited more than
// once. Consecutive rays from one origin whose slopes run monotonically (a scan's beams, as
// grouped by theta bin) are swept together. Rays must lie inside the window.
// Where a ray passes within rounding error of a cell corner or runs along a cell edge, the two
// may take different sides (both are exact up to rounding); real rays practically never do.
// The visitor goes in by value and comes back, as with std::for_each: a visitor holding its state
// by value (not through references) is swept with that state in registers.
// When all rays form one fan (one theta bin's beams of a scan), the columns where every ray is
// still under way are swept as one run per column: each of their cells is visited once and ends
// no ray. For those the sweep calls visit.once(slot) instead, if the visitor has it.
template <typename Visit>
Visit visitCellsOfRays(const std::vector<Ray>& rays, const uint32_t* order, size_t count,
                       double inverse_resolution, const RollingWindow& window, Visit visit) {
  using detail::FanRay;
  FanRay fan[detail::kMaxFanRays];
  size_t k = 0;
  while (k < count) {
    // Grow a fan from ray k while the rays share origin, major axis, direction and slope order.
    const Ray& head = rays[order[k]];
    const double start[2] = {head.origin.x() * inverse_resolution,
                             head.origin.y() * inverse_resolution};
    const Eigen::Vector2d head_delta = head.end - head.origin;
    const int major = std::abs(head_delta.x()) >= std::abs(head_delta.y()) ? 0 : 1;
    const int minor = 1 - major;
    const int step = head_delta[major] > 0 ? 1 : -1;
    const int column0 = floorToInt(start[major]);
    const int row0 = floorToInt(start[minor]);
    // From the start to the first column's far edge, along the major axis.
    const double first_edge =
        (step > 0 ? column0 + 1.0 : static_cast<double>(column0)) - start[major];
    int count_in_fan = 0;
    int slope_order = 0;  // +1 ascending, -1 descending, 0 not yet known
    double previous_slope = 0.0;
    for (; k < count && count_in_fan < detail::kMaxFanRays; ++k) {
      const Ray& ray = rays[order[k]];
      const Eigen::Vector2d delta = ray.end - ray.origin;
      if (ray.origin != head.origin ||
          (std::abs(delta.x()) >= std::abs(delta.y()) ? 0 : 1) != major ||
          (delta[major] > 0 ? 1 : -1) != step) {
        break;
      }
      const double end_major = ray.end[major] * inverse_resolution;
      const double end_minor = ray.end[minor] * inverse_resolution;
      const double run = end_major - start[major];
      const double slope = run != 0.0 ? (end_minor - start[minor]) / run : 0.0;
      if (count_in_fan > 0) {
        const int order_here = slope > previous_slope ? 1 : (slope < previous_slope ? -1 : 0);
        if (order_here != 0 && slope_order != 0 && order_here != slope_order) break;
        if (order_here != 0) slope_order = order_here;
      }
      previous_slope = slope;
      FanRay& entry = fan[count_in_fan++];
      entry.first_exit = detail::toFixed(start[minor] + first_edge * slope);
      entry.per_column = detail::toFixed(step * slope);
      const bool descending = end_minor < start[minor];
      entry.tie_bias = descending == (major == 0) ? 1 : 0;
      entry.columns = std::abs(floorToInt(end_major) - column0);
      entry.end_row = floorToInt(end_minor);
      entry.row_low = std::min(row0, entry.end_row);
      entry.row_high = std::max(row0, entry.end_row);
    }
    // A fan holding every ray of the call is the only one to visit the cells of its joined
    // columns, and no ray ends there: a visitor that offers once(slot) skips its
    // de-duplication for them.
    if constexpr (detail::HasOnce<Visit>::value) {
      if (k == count && k == static_cast<size_t>(count_in_fan)) {
        if (major == 0) {
          detail::sweepFan<0, true>(column0, row0, step, fan, count_in_fan, window, visit);
        } else {
          detail::sweepFan<1, true>(column0, row0, step, fan, count_in_fan, window, visit);
        }
        continue;
      }
    }
    if (major == 0) {
      detail::sweepFan<0, false>(column0, row0, step, fan, count_in_fan, window, visit);
    } else {
      detail::sweepFan<1, false>(column0, row0, step, fan, count_in_fan, window, visit);
    }
  }
  return visit;
}

}  // namespace rfm
