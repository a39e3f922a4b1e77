#include "reflectance_field_map/core/plain_occupancy_grid.h"

#include "reflectance_field_map/core/reflectance_field.h"

#include <algorithm>

namespace rfm {

struct PlainOccupancyGrid::Target {
  PlainOccupancyGrid& grid;
  void hit(int slot, int) { grid.cells_[slot] = grid.log_odds_.hit(grid.cells_[slot]); }
  void miss(int slot, int) { grid.cells_[slot] = grid.log_odds_.miss(grid.cells_[slot]); }
};

PlainOccupancyGrid::PlainOccupancyGrid(const GridOptions& grid, const LogOddsOptions& log_odds,
                                       const ActiveRegionOptions& region)
    : window_(grid.tile_cells,
              activeWindowTiles(region.active_region_radius, grid.resolution, grid.tile_cells)),
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
  const int t = window_.tileCells();
  for (const TileIndex& tile : shift.left) {
    const int x0 = window_.storageCoordinate(tile.x() * t);
    const int y0 = window_.storageCoordinate(tile.y() * t);
    for (int row = 0; row < t; ++row) {
      int8_t* first = &cells_[static_cast<size_t>(y0 + row) * window_.sizeCells() + x0];
      std::fill(first, first + t, 0);
    }
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
