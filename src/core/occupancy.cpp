#include "reflectance_field_map/core/occupancy.h"

#include <algorithm>
#include <cmath>

namespace rfm {

OccupancyRule::OccupancyRule(const OccupancyOptions& options, double bin_width)
    : options_(options),
      min_occupied_bins_(options.alpha / bin_width),
      metal_min_bins_(static_cast<int>(std::ceil(options.metal_min_angle / bin_width - 1e-9))) {}

int OccupancyRule::minWidelyVisibleBins(const LogOddsModel& model, int bins) const {
  const double bin_width = kTwoPi / bins;
  const double max_odds = model.odds(static_cast<int8_t>(model.maxValue()));
  if (max_odds <= 1.0) return bins + 1;  // nothing can beat the prior
  const double needed = (options_.beta / bin_width - bins) / (max_odds - 1.0);
  return std::max(1, static_cast<int>(std::floor(needed)) + 1);
}

}  // namespace rfm
