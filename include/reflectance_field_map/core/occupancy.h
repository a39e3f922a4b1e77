#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/core/reflectance_field.h"

namespace rfm {

// Projects the field to 2D (eq. 5 and eq. 7), before motion removal.
class OccupancyRule {
 public:
  OccupancyRule(const OccupancyOptions& options, double bin_width);

  // eq. 5: reflective angle (reflective bins * bin width) > alpha.
  bool isOccupied(int reflective_bins) const { return reflective_bins > min_occupied_bins_; }
  // Occupied, free (observed as missed) or unknown.
  CellClass classify(int reflective_bins, int missed_bins) const {
    if (isOccupied(reflective_bins)) return CellClass::kOccupied;
    return missed_bins > 0 ? CellClass::kFree : CellClass::kUnknown;
  }
  CellClass classify(const ReflectanceField& field, const CellIndex& cell) const {
    return classify(field.reflectiveBins(cell), field.missedBins(cell));
  }
  // eq. 7 against beta.
  bool isWidelyVisible(const ReflectanceField& field, const CellIndex& cell) const {
    return field.marginalOdds(cell) > options_.beta;
  }
  // Fewest reflective bins a widely visible cell can have: every other bin at most at the prior
  // (odds 1) and these at the clamp's maximum odds.
  int minWidelyVisibleBins(const LogOddsModel& model, int bins) const;
  // A glassy cell with a lobe at least this wide is metal.
  bool isMetalLobe(int reflective_bins) const { return reflective_bins >= metal_min_bins_; }

  const OccupancyOptions& options() const { return options_; }

 private:
  OccupancyOptions options_;
  double min_occupied_bins_;  // alpha / bin width
  int metal_min_bins_;
};

}  // namespace rfm
