#pragma once

// People left in a map: occupied cells that most of the scans observing them saw through
// (transient evidence). Static structure is hit whenever it is seen; a cell where a person stood
// for a while is seen through the rest of the time. ROS-free.

#include "reflectance_field_map/core/mapper.h"
#include "reflectance_field_map/tools/grid_map_file.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rfm::tools {

// Per cell of a box of the fixed frame's grid (cell = floor(point / resolution)), how many scans
// ended a beam in it and how many saw through it. A scan counts once per cell: if any of its
// beams ends in the cell it hit it, else if any crosses it, more than `margin_cells` cells
// before its end, it saw through it (range noise moves a wall's return across a cell boundary
// or two: that is no sight through). Beams without a return count neither way: a far or dark
// wall drops out now and then, which is no sight through it either.
class TransientEvidence {
 public:
  static constexpr int kDefaultMarginCells = 2;

  TransientEvidence(double resolution, int min_x, int min_y, int width, int height,
                    int margin_cells = kDefaultMarginCells);

  // Adds one scan, taken at scan.sensor_pose.
  void addScan(const TimedScan& scan);

  double resolution() const { return resolution_; }
  uint32_t hitScans(int cell_x, int cell_y) const;
  uint32_t passedScans(int cell_x, int cell_y) const;
  // Seen through by more of the scans that observed it than hit it.
  bool isTransient(int cell_x, int cell_y) const {
    return passedScans(cell_x, cell_y) > hitScans(cell_x, cell_y);
  }

 private:
  bool inBox(int x, int y) const {
    return x >= min_x_ && y >= min_y_ && x < min_x_ + width_ && y < min_y_ + height_;
  }
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y - min_y_) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(x - min_x_);
  }

  double resolution_;
  int min_x_, min_y_, width_, height_;
  int margin_cells_;
  std::vector<uint32_t> hits_, passes_;
  std::vector<uint32_t> last_hit_scan_, last_pass_scan_;  // 1-based scan numbers, 0: none
  uint32_t scans_ = 0;
};

// The fixed frame's cell of a map's cell (x, y): the map's origin is a whole number of cells
// (rfm_offline writes it so). Throws MapFileError when it is not.
void mapCellOrigin(const GridMap& map, int& cell_x, int& cell_y);

struct PeopleLeft {
  std::size_t occupied = 0;   // the map's occupied cells
  std::size_t transient = 0;  // of those, transient: people left in the map
};
PeopleLeft measurePeopleLeft(const GridMap& map, const TransientEvidence& evidence);

}  // namespace rfm::tools
