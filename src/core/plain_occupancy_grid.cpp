#include "reflectance_field_map/core/plain_occupancy_grid.h"

#include "reflectance_field_map/core/reflectance_field.h"

#include <algorithm>

namespace rfm {

struct PlainOccupancyGrid::Target {
  PlainOccupancyGrid& grid;
  // Values held locally, as in detail::SliceWriter, so the two compare fairly.
  struct Writer {
    int8_t* cells;
    int hit_step, miss_step, min, max;
    void hit(int slot) {
      const int updated = cells[slot] + hit_step;
      cells[slot] = static_cast<int8_t>(updated > max ? max : updated);
    }
    void miss(int slot) {
      const int updated = cells[slot] + miss_step;
      cells[slot] = static_cast<int8_t>(updated < min ? min : updated);
    }
  };
  Writer writer(int) {
    return {grid.cells_.data(), grid.log_odds_.hitStep(), grid.log_odds_.missStep(),
            grid.log_odds_.minValue(), grid.log_odds_.maxValue()};
  }
};

PlainOccupancyGrid::PlainOccupancyGrid(const GridOptions& grid, const LogOddsOptions& log_odds,
                                       const ActiveRegionOptions& region, double window_radius)
    : window_(grid.tile_cells,
              activeWindowTiles(std::max(region.active_region_radius, window_radius),
                                grid.resolution, grid.tile_cells)),
      resolution_(grid.resolution),
      log_odds_(log_odds),
      cells_(static_cast<size_t>(window_.sizeCells()) * window_.sizeCells(), 0) {}

void PlainOccupancyGrid::recenter(const Eigen::Vector2d& robot_position) {
  const CellIndex cell(static_cast<int>(std::floor(robot_position.x() / resolution_)),
                       static_cast<int>(std::floor(robot_position.y() / resolution_)));
  const TileIndex origin = window_.originCentredOn(cell);
  if (!centred_) {
    centred_ = true;
    window_.setOrigin(origin);
    return;
  }
  const WindowShift shift = diffWindows(window_, origin);
  const size_t tile_slots = static_cast<size_t>(window_.tileCells()) * window_.tileCells();
  for (const TileIndex& tile : shift.left) {
    std::fill_n(&cells_[window_.tileFirstSlot(tile)], tile_slots, 0);
  }
  window_.setOrigin(origin);
}

size_t PlainOccupancyGrid::insert(const std::vector<Ray>& rays) {
  clipped_.clear();
  for (const Ray& ray : rays) {
    Ray clipped = ray;
    if (clipRayToBox(window_.box(), resolution_, clipped)) clipped_.push_back(clipped);
  }
  order_.resize(clipped_.size());
  for (size_t i = 0; i < order_.size(); ++i)
    order_[i] = static_cast<uint32_t>(i);
  group_begin_ = {0, static_cast<uint32_t>(clipped_.size())};
  Target target{*this};
  inserter_.insert(window_, 1.0 / resolution_, clipped_, order_, group_begin_, target);
  return inserter_.updates();
}

}  // namespace rfm
