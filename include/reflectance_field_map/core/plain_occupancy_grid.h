#pragma once

#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/log_odds.h"
#include "reflectance_field_map/core/ray_insertion.h"
#include "reflectance_field_map/core/rolling_window.h"

#include <cstdint>
#include <vector>

namespace rfm {

// A standard 2D log-odds occupancy grid over the same rolling window and the same ray
// traversal: the paper's baseline (Table II) and the performance yardstick of the RFM.
class PlainOccupancyGrid {
 public:
  PlainOccupancyGrid(const GridOptions& grid, const LogOddsOptions& log_odds,
                     const ActiveRegionOptions& region, double window_radius = 0.0);

  const RollingWindow& window() const { return window_; }
  double resolution() const { return resolution_; }
  // Scrolls like the RFM; cells that leave are forgotten (the baseline keeps no history).
  void recenter(const Eigen::Vector2d& robot_position);
  size_t insert(const std::vector<Ray>& rays);

  int8_t value(const CellIndex& cell) const { return cells_[window_.storageIndex(cell)]; }
  bool isOccupied(const CellIndex& cell) const { return value(cell) > 0; }
  bool isFree(const CellIndex& cell) const { return value(cell) < 0; }
  size_t bytes() const { return cells_.size(); }

 private:
  struct Target;

  RollingWindow window_;
  double resolution_;
  LogOddsModel log_odds_;
  bool centred_ = false;
  std::vector<int8_t> cells_;
  std::vector<Ray> clipped_;
  std::vector<uint32_t> order_;
  std::vector<uint32_t> group_begin_;
  DeduplicatingRayInserter inserter_;
};

}  // namespace rfm
