#pragma once

#include "reflectance_field_map/core/grid_geometry.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace rfm {

// Exact grid traversal (Amanatides & Woo): visits every cell the segment start -> end passes
// through, in order, from the cell of `start` to the cell of `end` inclusive. The step count
// is fixed up front from the integer end cell, so floating-point drift can never overshoot
// or stop early: when the parametric choice disagrees with the remaining steps, the axis that
// still has steps left is taken.
class GridRayTraversal {
 public:
  GridRayTraversal(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                   double inverse_resolution) {
    const Eigen::Vector2d from = start * inverse_resolution;
    const Eigen::Vector2d to = end * inverse_resolution;
    cell_ = {floorToInt(from.x()), floorToInt(from.y())};
    const CellIndex last(floorToInt(to.x()), floorToInt(to.y()));
    const Eigen::Vector2d delta = to - from;
    for (int axis = 0; axis < 2; ++axis) {
      step_[axis] = delta[axis] > 0 ? 1 : -1;
      remaining_[axis] = std::abs(last[axis] - cell_[axis]);
      if (delta[axis] == 0.0) {
        t_max_[axis] = std::numeric_limits<double>::infinity();
        t_delta_[axis] = std::numeric_limits<double>::infinity();
      } else {
        const double boundary = step_[axis] > 0 ? cell_[axis] + 1.0 : cell_[axis];
        t_max_[axis] = (boundary - from[axis]) / delta[axis];
        t_delta_[axis] = std::abs(1.0 / delta[axis]);
      }
    }
  }

  const CellIndex& cell() const { return cell_; }
  // Cells still to visit after the current one.
  int remaining() const { return remaining_[0] + remaining_[1]; }
  bool atEnd() const { return remaining() == 0; }
  int step(int axis) const { return step_[axis]; }

  // Moves to the next cell; returns the axis stepped (0 = x, 1 = y). Requires !atEnd().
  int next() {
    int axis = t_max_[0] < t_max_[1] ? 0 : 1;
    if (remaining_[axis] == 0) axis = 1 - axis;  // drift guard
    cell_[axis] += step_[axis];
    t_max_[axis] += t_delta_[axis];
    --remaining_[axis];
    return axis;
  }

 private:
  CellIndex cell_;
  int step_[2];
  int remaining_[2];
  double t_max_[2];
  double t_delta_[2];
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

}  // namespace rfm
