// The paper's per-ray classification (Sec. VI-A): each beam of a scan kept, or removed as
// motion or reflection, against a map.
#pragma once

#include "reflectance_field_map/core/active_classes.h"
#include "reflectance_field_map/core/arrival_marks.h"
#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/reflectance_field.h"
#include "reflectance_field_map/core/reflection_removal.h"

#include <vector>

namespace rfm {

// How a beam's endpoint is judged against a map (paper Sec. VI-A): kept when the end cell, or one
// of its 8 neighbours (discretisation), is an obstacle; otherwise its evidence did not survive:
// motion (a transient object, or erased evidence when `final_map`). A beam longer than the
// evidence range (active_region_radius) added nothing at its end: an end cell that no ray
// observed leaves it unjudged (kept), against the final map too, as live. Live, a return in a cell
// the last classification left free, with nothing but free or unknown cells beside it, is motion
// when `arrived(end_cell)` says something arrived there (arrivedInFreeCell), else kept until
// motion removal judges it.
template <typename ClassOf, typename Arrived>
RayLabel labelEndpoint(const Ray& beam, const GridGeometry& geometry, double evidence_range,
                       bool final_map, ClassOf&& class_of, Arrived&& arrived) {
  // An end past every cell a map can hold (a return claimed from 1e19 m) lies in no map:
  // unjudged.
  const double limit = GlobalMap2D::kMaxCellCoordinate;
  if (!(beam.end.array().abs() * geometry.inverseResolution() < limit).all()) {
    return RayLabel::kKept;
  }
  const CellIndex end_cell = geometry.cellOf(beam.end);
  bool motion = false;
  const CellClass c = class_of(end_cell);
  if (isObstacle(c)) return RayLabel::kKept;
  motion |= c == CellClass::kMotion;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const CellClass n = class_of(CellIndex(end_cell.x() + dx, end_cell.y() + dy));
      if (isObstacle(n)) return RayLabel::kKept;
      motion |= n == CellClass::kMotion;
    }
  }
  if (motion) return RayLabel::kMotion;
  if (!final_map) {
    return c == CellClass::kFree && arrived(end_cell) ? RayLabel::kMotion : RayLabel::kKept;
  }
  const bool judged = c != CellClass::kUnknown || (beam.end - beam.origin).norm() <= evidence_range;
  return judged ? RayLabel::kMotion : RayLabel::kKept;  // unjudged: kept for safety
}

// Whether a just-inserted return `beam` in `cell` is an arrival: the field had seen the cell free
// in the beam's own direction before this return (its bin, this scan's hit included, is below
// one hit), as open floor a person steps into. A surface first seen from a direction no ray had
// crossed it in (a pane near its normal, seen through only from elsewhere) is not one.
bool arrivedInFreeCell(const ReflectanceField& field, const Ray& beam, const CellIndex& cell);

// Whether that return met a bin at the lower clamp: the cell was seen free firmly in the beam's
// direction (five misses and more at the defaults), not glimpsed free between returns, as the
// cells of a pane at the edge of its return cone are while the cone moves along it.
bool arrivedInFirmlyFreeCell(const ReflectanceField& field, const Ray& beam, const CellIndex& cell);

// Whether `ray` goes on through `cell`: its line passes within half a cell's diagonal of the
// cell's centre, ahead of its origin and short of its last cell.
bool passesThroughCell(const Ray& ray, const CellIndex& cell, const GridGeometry& geometry);

// The labels of a scan's `rays` (in beam order, of a scan of `beams` beams) against the active
// region's classes: REFLECTION where the reflection check finds the ray passing through a
// blocking cell (its part inside the window), else as labelEndpoint judges it; NO_RETURN for
// beams without a return. Beams marked in `checked_beams` (by beam; null or empty: none) skip
// the reflection check: the caller already knows its answer for them. `inserted` (live: the field
// that holds these rays' hits; null: none) judges returns in free cells: an arrival when
// arrivedInFreeCell and neither neighbouring beam of the scan passesThroughCell. With `arrivals`
// (may be null) such an arrival is marked there when arrivedInFirmlyFreeCell, and a return in a
// free cell at or beside a marked one is an arrival too: the same object, whose earlier hits
// filled the bin.
std::vector<RayLabel> labelRays(const std::vector<Ray>& rays, size_t beams,
                                const ReflectionRemover& reflections, const ActiveClasses& classes,
                                const CellBox& window_box, const GridGeometry& geometry,
                                double evidence_range, bool final_map,
                                const std::vector<uint8_t>* checked_beams = nullptr,
                                const ReflectanceField* inserted = nullptr,
                                ArrivalMarks* arrivals = nullptr);

}  // namespace rfm
