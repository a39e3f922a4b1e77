// The exact grid traversal (Amanatides & Woo) that every cell-by-cell walk along a ray uses.
#pragma once

#include "reflectance_field_map/core/detail/compiler.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/rolling_window.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace rfm {
namespace detail {

// The traversal's state, in scalars: per-axis arrays indexed by the axis just stepped would
// make the compiler keep them in memory, a store-to-load round trip per step.
// The step count is fixed up front from the integer end cell, so floating-point drift can never
// overshoot or stop early: when the parametric choice disagrees with the remaining steps, the
// axis that still has steps left is taken.
struct CellStepper {
  CellStepper(const Eigen::Vector2d& start, const Eigen::Vector2d& end, double inverse_resolution) {
    const double fx = start.x() * inverse_resolution, fy = start.y() * inverse_resolution;
    const double ex = end.x() * inverse_resolution, ey = end.y() * inverse_resolution;
    x = floorToInt(fx);
    y = floorToInt(fy);
    const double dx = ex - fx, dy = ey - fy;
    remaining_x = std::abs(floorToInt(ex) - x);
    remaining_y = std::abs(floorToInt(ey) - y);
    step_x = dx > 0 ? 1 : -1;
    step_y = dy > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    t_max_x = dx == 0.0 ? inf : ((step_x > 0 ? x + 1.0 : x) - fx) / dx;
    t_max_y = dy == 0.0 ? inf : ((step_y > 0 ? y + 1.0 : y) - fy) / dy;
    t_delta_x = dx == 0.0 ? inf : std::abs(1.0 / dx);
    t_delta_y = dy == 0.0 ? inf : std::abs(1.0 / dy);
  }

  // Cells still to visit after the current one.
  int remaining() const { return remaining_x + remaining_y; }

  // Moves to the next cell; true when it stepped along x, false along y. Past the end cell it
  // steps on harmlessly (a walk may take one step after its last visit).
  RFM_ALWAYS_INLINE bool next() {
    // Parametric choice, overruled when that axis has no steps left (drift guard).
    if (t_max_x < t_max_y ? remaining_x > 0 : remaining_y == 0) {
      t_max_x += t_delta_x;
      --remaining_x;
      x += step_x;
      return true;
    }
    t_max_y += t_delta_y;
    --remaining_y;
    y += step_y;
    return false;
  }

  int x, y;  // the current cell
  int remaining_x, remaining_y;
  int step_x, step_y;
  double t_max_x, t_max_y, t_delta_x, t_delta_y;
};

}  // namespace detail

// Visits every cell the segment start -> end passes through, in order, from the cell of `start`
// to the cell of `end` inclusive.
class GridRayTraversal {
 public:
  GridRayTraversal(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                   double inverse_resolution)
      : stepper_(start, end, inverse_resolution) {}

  CellIndex cell() const { return {stepper_.x, stepper_.y}; }
  // Cells still to visit after the current one.
  int remaining() const { return stepper_.remaining(); }
  bool atEnd() const { return remaining() == 0; }

  // Moves to the next cell; returns the axis stepped (0 = x, 1 = y). Requires !atEnd().
  int next() { return stepper_.next() ? 0 : 1; }

 private:
  detail::CellStepper stepper_;
};

// Calls visit(cell) for every cell of the traversal, in order.
template <typename Visitor>
void forEachCellOnRay(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                      double inverse_resolution, Visitor&& visit) {
  GridRayTraversal traversal(start, end, inverse_resolution);
  visit(traversal.cell());
  while (!traversal.atEnd()) {
    traversal.next();
    visit(traversal.cell());
  }
}

// Like forEachCellOnRay, stopping as soon as visit(cell) returns false.
template <typename Visitor>
void forEachCellOnRayWhile(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                           double inverse_resolution, Visitor&& visit) {
  GridRayTraversal traversal(start, end, inverse_resolution);
  if (!visit(traversal.cell())) return;
  while (!traversal.atEnd()) {
    traversal.next();
    if (!visit(traversal.cell())) return;
  }
}

// The traversal's cells as window storage slots: calls visit(slot, cell_x, cell_y) for each
// cell up to the end cell (included when `include_end`); the walk stops early when visit
// returns false. The ray must lie inside the window.
template <typename Visit>
inline void walkWindowCells(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                            double inverse_resolution, const RollingWindow& window,
                            bool include_end, Visit&& visit) {
  detail::CellStepper walk(start, end, inverse_resolution);
  // Indices into the offset tables, which wrap the ray (inside the window) around storage.
  int column = walk.x - window.offsetOrigin().x(), row = walk.y - window.offsetOrigin().y();
  const int* const column_offsets = window.columnOffsets();
  const int* const row_offsets = window.rowOffsets();
  int cells = walk.remaining() + (include_end ? 1 : 0);
  while (cells-- > 0) {
    if (!visit(column_offsets[column] + row_offsets[row], walk.x, walk.y)) return;
    if (walk.next()) {
      column += walk.step_x;
    } else {
      row += walk.step_y;
    }
  }
}

}  // namespace rfm
