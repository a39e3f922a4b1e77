#include "reflectance_field_map/core/options.h"

#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/log_odds.h"

#include <cmath>
#include <sstream>
#include <type_traits>

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
}

void OccupancyOptions::validate() const {
  requireRange("alpha", alpha, 0.0, kTwoPi);
  // Unobserved bins have odds 1, so any cell sums to about 2*pi: beta must lie above that.
  requireRange("beta", beta, kTwoPi, 10000.0, true);
  requireRange("metal_min_angle", metal_min_angle, 0.0, kTwoPi);
}

void MotionRemovalOptions::validate() const {
  requireRange("motion_removal_rate", motion_removal_rate, 0.01, 100.0);
  requireRange("persistence_time", persistence_time, 0.0, 1e6);
  requireRange("persistence_min_length", persistence_min_length, 0.0, 100.0);
  requireRange("departure_min_angle", departure_min_angle, 0.0, kTwoPi);
  requireRange("departure_vacant_time", departure_vacant_time, 0.0, 1e6);
  requireRange("solid_max_missed_ratio", solid_max_missed_ratio, 0.0, 1000.0);
  requireRange("solid_min_share", solid_min_share, 0.0, 1.0);
  requireRange("solid_anchor_min_angle", solid_anchor_min_angle, 0.0, kTwoPi);
  requireRange("glass_max_static_neighbours", glass_max_static_neighbours, -1, 8);
  requireRange("column_max_radius", column_max_radius, 0.0, 10.0);
}

void ReflectionRemovalOptions::validate() const {
  requireRange("penetration_tolerance", penetration_tolerance, 0.0, 5.0);
  requireRange("glass_completion_max_gap", glass_completion_max_gap, 0.0, 20.0);
  requireRange("scan_buffer_size", scan_buffer_size, 0, 100000);
  requireRange("static_blocking_min_angle", static_blocking_min_angle, 0.0, kTwoPi);
}

void BatchOptions::validate() const {
  requireRange("batch_beta", batch_beta, kTwoPi, 10000.0, true);
  requireRange("max_reflection_iterations", max_reflection_iterations, 1, 100);
  requireRange("first_pass_scan_stride", first_pass_scan_stride, 1, 1000);
  requireRange("search_pass_scan_stride", search_pass_scan_stride, 1, 1000);
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

template <typename T>
constexpr OptionField::Type typeOf() {
  if constexpr (std::is_same_v<T, bool>) {
    return OptionField::Type::kBool;
  } else if constexpr (std::is_same_v<T, int>) {
    return OptionField::Type::kInt;
  } else {
    return OptionField::Type::kDouble;
  }
}

template <typename Options>
std::vector<OptionField> fieldsOf() {
  std::vector<OptionField> out;
  const Options defaults;
  Options::forEachParameter(
      defaults, [&](const char* name, const char* description, const auto& field) {
        out.push_back({name, description, typeOf<std::decay_t<decltype(field)>>()});
      });
  return out;
}

template <typename Options>
bool setField(Options& options, const std::string& name, double value) {
  bool found = false;
  Options::forEachParameter(options, [&](const char* field_name, const char*, auto& field) {
    if (found || name != field_name) return;
    found = true;
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, bool>) {
      field = value != 0.0;
    } else if constexpr (std::is_same_v<T, int>) {
      field = static_cast<int>(std::lround(value));
    } else {
      field = value;
    }
  });
  return found;
}

template <typename Options>
double getField(const Options& options, const std::string& name) {
  double value = 0.0;
  bool found = false;
  Options::forEachParameter(options, [&](const char* field_name, const char*, const auto& field) {
    if (found || name != field_name) return;
    found = true;
    value = static_cast<double>(field);
  });
  if (!found) throw std::invalid_argument("unknown option " + name);
  return value;
}

}  // namespace

const std::vector<OptionField>& optionFields() {
  static const std::vector<OptionField> fields = fieldsOf<MapperOptions>();
  return fields;
}

const std::vector<OptionField>& batchOptionFields() {
  static const std::vector<OptionField> fields = fieldsOf<BatchOptions>();
  return fields;
}

bool setOption(MapperOptions& options, const std::string& name, double value) {
  return setField(options, name, value);
}

bool setOption(BatchOptions& options, const std::string& name, double value) {
  return setField(options, name, value);
}

double getOption(const MapperOptions& options, const std::string& name) {
  return getField(options, name);
}

double getOption(const BatchOptions& options, const std::string& name) {
  return getField(options, name);
}

}  // namespace rfm
