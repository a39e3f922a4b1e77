// Where a robot or a person of a given size can go in a world: a grid of clearances (distance to
// the nearest surface), shortest paths on it and straight-line visibility. The procedural scene
// generator plans every walk and drive with it. ROS-free.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vector>

#include "reflectance_field_map/sim/world.h"

namespace rfm::sim {

class NavigationGrid {
 public:
  // Rasterises every static surface of `world` within [low, high] at `resolution` (m) and computes
  // each cell's distance to the nearest surface cell (cells outside the box count as surface).
  NavigationGrid(const World& world, const Eigen::Vector2d& low, const Eigen::Vector2d& high,
                 double resolution);

  // Distance (m) from the centre of the cell holding `point` to the nearest surface; 0 outside.
  double clearance(const Eigen::Vector2d& point) const;
  // Whether the straight line from a to b keeps at least `clearance` from every surface.
  bool lineClear(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double clearance) const;
  // Shortest path from `start` to `goal` through cells with at least `clearance` that `allowed`
  // accepts (all when empty), shortened to the corners it needs; nothing when there is none.
  std::optional<std::vector<Eigen::Vector2d>> path(
      const Eigen::Vector2d& start, const Eigen::Vector2d& goal, double clearance,
      const std::function<bool(const Eigen::Vector2d&)>& allowed = {}) const;
  // Every cell centre with at least `clearance` inside the box [low, high].
  std::vector<Eigen::Vector2d> freeCells(const Eigen::Vector2d& low, const Eigen::Vector2d& high,
                                         double clearance) const;

  double resolution() const { return resolution_; }

 private:
  std::optional<int> cellIndex(const Eigen::Vector2d& point) const;
  Eigen::Vector2d cellCentre(int index) const;

  Eigen::Vector2d low_;
  double resolution_;
  int width_ = 0, height_ = 0;
  std::vector<float> clearance_;  // metres, per cell
};

}  // namespace rfm::sim
