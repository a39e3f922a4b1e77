#pragma once

#include "reflectance_field_map/core/options.h"

namespace rfm::fuzz {

// A mapper small enough for thousands of runs a second (a 2 m region at 10 cm, 16 directions),
// 8-cell tiles, one thread; the mapper_load seeds are saved with these options, which a load must
// match.
inline MapperOptions smallMapperOptions() {
  MapperOptions options;
  options.grid.resolution = 0.1;
  options.grid.theta_bins = 16;
  options.grid.tile_cells = 8;
  options.active_region.active_region_radius = 2.0;
  options.insertion.insertion_threads = 1;
  return options;
}

}  // namespace rfm::fuzz
