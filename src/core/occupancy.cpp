#include "reflectance_field_map/core/occupancy.h"

#include <cmath>

namespace rfm {

OccupancyRule::OccupancyRule(const OccupancyOptions& options, double bin_width)
    : options_(options),
      min_occupied_bins_(options.alpha / bin_width),
      metal_min_bins_(static_cast<int>(std::ceil(options.metal_min_angle / bin_width - 1e-9))) {}

}  // namespace rfm
