#include "reflectance_field_map/core/options.h"

#include "reflectance_field_map/core/clearance_map.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/log_odds.h"

#include <cmath>
#include <functional>
#include <sstream>

namespace rfm {
namespace {

std::string str(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void requireRange(const char* field, double value, double low, double high, bool low_open = false) {
  const bool ok = std::isfinite(value) && (low_open ? value > low : value >= low) && value <= high;
  if (!ok) {
    throw InvalidOption(field, str(value),
                        std::string(low_open ? "(" : "[") + str(low) + ", " + str(high) + "]");
  }
}

constexpr double kMaxLogOdds = 127 * LogOddsModel::kQuantum;

}  // namespace

void GridOptions::validate() const {
  requireRange("resolution", resolution, 0.005, 1.0);
  requireRange("theta_bins", theta_bins, 4, 1440);
  requireRange("tile_cells", tile_cells, 4, 128);
  if ((tile_cells & (tile_cells - 1)) != 0) {
    throw InvalidOption("tile_cells", str(tile_cells), "a power of two in [4, 128]");
  }
}

void LogOddsOptions::validate() const {
  requireRange("log_odds_hit", log_odds_hit, LogOddsModel::kQuantum, kMaxLogOdds);
  requireRange("log_odds_miss", log_odds_miss, -kMaxLogOdds, -LogOddsModel::kQuantum);
  requireRange("log_odds_max", log_odds_max, LogOddsModel::kQuantum, kMaxLogOdds);
  requireRange("log_odds_min", log_odds_min, -kMaxLogOdds, -LogOddsModel::kQuantum);
}

void InsertionOptions::validate() const {
  requireRange("clearing_distance", clearing_distance, 0.0, 100.0);
  requireRange("insertion_threads", insertion_threads, 1, 16);
}

void ActiveRegionOptions::validate() const {
  requireRange("active_region_radius", active_region_radius, 1.0, 200.0);
  requireRange("window_radius", window_radius, 0.0, kMaxWindowRadius);
}

void OccupancyOptions::validate() const {
  requireRange("alpha", alpha, 0.0, kTwoPi);
  // Unobserved bins have odds 1, so any cell sums to about 2*pi: beta must lie above that.
  requireRange("beta", beta, kTwoPi, 10000.0, true);
  requireRange("batch_beta", batch_beta, kTwoPi, 10000.0, true);
  requireRange("metal_min_angle", metal_min_angle, 0.0, kTwoPi);
}

void MotionRemovalOptions::validate() const {
  requireRange("motion_removal_rate", motion_removal_rate, 0.01, 100.0);
  requireRange("persistence_time", persistence_time, 0.0, 1e6);
  requireRange("persistence_min_length", persistence_min_length, 0.0, 100.0);
  requireRange("departure_min_angle", departure_min_angle, 0.0, kTwoPi);
  requireRange("departure_vacant_time", departure_vacant_time, 0.0, 1e6);
  requireRange("opaque_min_angle", opaque_min_angle, 0.0, kTwoPi);
  requireRange("opaque_min_length", opaque_min_length, 0.0, 100.0);
}

void ReflectionRemovalOptions::validate() const {
  requireRange("penetration_tolerance", penetration_tolerance, 0.0, 5.0);
  requireRange("max_reflection_iterations", max_reflection_iterations, 1, 100);
  requireRange("first_pass_scan_stride", first_pass_scan_stride, 1, 1000);
  requireRange("search_pass_scan_stride", search_pass_scan_stride, 1, 1000);
  requireRange("glass_completion_max_gap", glass_completion_max_gap, 0.0, 20.0);
  requireRange("scan_buffer_size", scan_buffer_size, 0, 100000);
  requireRange("clearance_block_shift", clearance_block_shift, 0, ClearanceMap::kMaxBlockShift);
}

void MapperOptions::validate() const {
  grid.validate();
  log_odds.validate();
  insertion.validate();
  active_region.validate();
  occupancy.validate();
  motion_removal.validate();
  reflection_removal.validate();
  if (active_region.active_region_radius < 2 * grid.tile_cells * grid.resolution) {
    throw InvalidOption("active_region_radius", str(active_region.active_region_radius),
                        ">= 2 tiles (2 * tile_cells * resolution = " +
                            str(2 * grid.tile_cells * grid.resolution) + " m)");
  }
}

namespace {

struct FieldAccess {
  OptionField field;
  std::function<double&(MapperOptions&)> real;
  std::function<int&(MapperOptions&)> integer;
  std::function<bool&(MapperOptions&)> flag;
};

const std::vector<FieldAccess>& accessTable() {
  using T = OptionField::Type;
  static const std::vector<FieldAccess> table = {
      {{"resolution", "cell size (m)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.grid.resolution; },
       {},
       {}},
      {{"theta_bins", "direction bins over 2*pi", T::kInt},
       {},
       [](MapperOptions& o) -> int& { return o.grid.theta_bins; },
       {}},
      {{"tile_cells", "cells per tile side", T::kInt},
       {},
       [](MapperOptions& o) -> int& { return o.grid.tile_cells; },
       {}},
      {{"log_odds_hit", "log-odds added by a hit", T::kDouble},
       [](MapperOptions& o) -> double& { return o.log_odds.log_odds_hit; },
       {},
       {}},
      {{"log_odds_miss", "log-odds added by a miss", T::kDouble},
       [](MapperOptions& o) -> double& { return o.log_odds.log_odds_miss; },
       {},
       {}},
      {{"log_odds_min", "lower clamp of a bin", T::kDouble},
       [](MapperOptions& o) -> double& { return o.log_odds.log_odds_min; },
       {},
       {}},
      {{"log_odds_max", "upper clamp of a bin", T::kDouble},
       [](MapperOptions& o) -> double& { return o.log_odds.log_odds_max; },
       {},
       {}},
      {{"clearing_distance", "misses for beams with no return (m)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.insertion.clearing_distance; },
       {},
       {}},
      {{"insertion_threads", "threads inserting a scan, split by theta bin", T::kInt},
       {},
       [](MapperOptions& o) -> int& { return o.insertion.insertion_threads; },
       {}},
      {{"active_region_radius", "robot-centred region updated each scan (m)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.active_region.active_region_radius; },
       {},
       {}},
      {{"alpha", "eq. 5: min reflective angle of an obstacle (rad)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.occupancy.alpha; },
       {},
       {}},
      {{"beta", "eq. 7: min marginal odds of a widely visible cell (rad)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.occupancy.beta; },
       {},
       {}},
      {{"batch_beta", "batch: eq. 7 threshold of the offline tool (rad)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.occupancy.batch_beta; },
       {},
       {}},
      {{"metal_min_angle", "min reflective angle of metal (rad)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.occupancy.metal_min_angle; },
       {},
       {}},
      {{"motion_removal_enabled", "run Alg. 2", T::kBool},
       {},
       {},
       [](MapperOptions& o) -> bool& { return o.motion_removal.motion_removal_enabled; }},
      {{"motion_removal_rate", "motion removal timer (Hz)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.motion_removal.motion_removal_rate; },
       {},
       {}},
      {{"persistence_time", "reflective this long without a break anchors like V (s, 0 off)",
        T::kDouble},
       [](MapperOptions& o) -> double& { return o.motion_removal.persistence_time; },
       {},
       {}},
      {{"persistence_min_length", "persistent cells anchor components at least this long (m)",
        T::kDouble},
       [](MapperOptions& o) -> double& { return o.motion_removal.persistence_min_length; },
       {},
       {}},
      {{"departure_min_angle",
        "seen through over this much of its former reflective angle: anchors no more (rad, 0 off)",
        T::kDouble},
       [](MapperOptions& o) -> double& { return o.motion_removal.departure_min_angle; },
       {},
       {}},
      {{"departure_vacant_time",
        "seen through in new directions, never hit, this long: anchors no more (s, 0 off)",
        T::kDouble},
       [](MapperOptions& o) -> double& { return o.motion_removal.departure_vacant_time; },
       {},
       {}},
      {{"opaque_min_angle", "reflective this wide and never seen through anchors (rad, 0 off)",
        T::kDouble},
       [](MapperOptions& o) -> double& { return o.motion_removal.opaque_min_angle; },
       {},
       {}},
      {{"opaque_min_length", "never-seen-through cells anchor components this long (m)",
        T::kDouble},
       [](MapperOptions& o) -> double& { return o.motion_removal.opaque_min_length; },
       {},
       {}},
      {{"reflection_removal_enabled", "run Alg. 3", T::kBool},
       {},
       {},
       [](MapperOptions& o) -> bool& { return o.reflection_removal.reflection_removal_enabled; }},
      {{"penetration_tolerance", "ray may end this far past glass (m)", T::kDouble},
       [](MapperOptions& o) -> double& { return o.reflection_removal.penetration_tolerance; },
       {},
       {}},
      {{"max_reflection_iterations", "batch re-processing passes", T::kInt},
       {},
       [](MapperOptions& o) -> int& { return o.reflection_removal.max_reflection_iterations; },
       {}},
      {{"first_pass_scan_stride", "batch: first pass inserts every Nth scan of each sensor",
        T::kInt},
       {},
       [](MapperOptions& o) -> int& { return o.reflection_removal.first_pass_scan_stride; },
       {}},
      {{"search_pass_scan_stride",
        "batch: later passes but the last insert every Nth scan of each sensor", T::kInt},
       {},
       [](MapperOptions& o) -> int& { return o.reflection_removal.search_pass_scan_stride; },
       {}},
      {{"glass_completion_max_gap", "free stretch of a glass line taken as glass (m, 0 off)",
        T::kDouble},
       [](MapperOptions& o) -> double& { return o.reflection_removal.glass_completion_max_gap; },
       {},
       {}},
      {{"scan_buffer_size", "scans kept for online re-processing", T::kInt},
       {},
       [](MapperOptions& o) -> int& { return o.reflection_removal.scan_buffer_size; },
       {}},
  };
  return table;
}

const FieldAccess* findField(const std::string& name) {
  for (const FieldAccess& access : accessTable()) {
    if (access.field.name == name) return &access;
  }
  return nullptr;
}

}  // namespace

const std::vector<OptionField>& optionFields() {
  static const std::vector<OptionField> fields = [] {
    std::vector<OptionField> out;
    for (const FieldAccess& access : accessTable())
      out.push_back(access.field);
    return out;
  }();
  return fields;
}

bool setOption(MapperOptions& options, const std::string& name, double value) {
  const FieldAccess* access = findField(name);
  if (access == nullptr) return false;
  switch (access->field.type) {
    case OptionField::Type::kDouble:
      access->real(options) = value;
      break;
    case OptionField::Type::kInt:
      access->integer(options) = static_cast<int>(std::lround(value));
      break;
    case OptionField::Type::kBool:
      access->flag(options) = value != 0.0;
      break;
  }
  return true;
}

double getOption(const MapperOptions& options, const std::string& name) {
  const FieldAccess* access = findField(name);
  if (access == nullptr) throw std::invalid_argument("unknown option " + name);
  auto& mutable_options = const_cast<MapperOptions&>(options);
  switch (access->field.type) {
    case OptionField::Type::kDouble:
      return access->real(mutable_options);
    case OptionField::Type::kInt:
      return access->integer(mutable_options);
    case OptionField::Type::kBool:
      return access->flag(mutable_options) ? 1.0 : 0.0;
  }
  return 0.0;
}

}  // namespace rfm
