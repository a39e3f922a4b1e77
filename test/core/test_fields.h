#pragma once

// Reflectance fields for tests that write evidence directly.

#include "reflectance_field_map/core/reflectance_field.h"

namespace rfm {
namespace testing {

inline ActiveRegionOptions regionOfRadius(double radius) {
  ActiveRegionOptions region;
  region.active_region_radius = radius;
  return region;
}

// A field of `radius` (m) centred on the origin.
inline ReflectanceField centredField(double radius, const GridOptions& grid = GridOptions()) {
  ReflectanceField field(grid, LogOddsOptions(), regionOfRadius(radius));
  field.recenter({0.0, 0.0});
  return field;
}

}  // namespace testing
}  // namespace rfm
