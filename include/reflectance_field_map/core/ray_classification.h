#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/ray_traversal.h"

#include <Eigen/Core>

namespace rfm {

// Cells a ray cannot pass through without its return being untrustworthy (Alg. 3).
inline bool blocksRays(CellClass c) {
  return c == CellClass::kGlass || c == CellClass::kMetal || c == CellClass::kStatic;
}

// Reflection check of Alg. 3: walks the ray and returns the distance (m, along the ray) of the
// first blocking cell that the ray passes through, or a negative value. A blocking cell is glass
// or metal, or static and not reflective in the ray's direction (+-1 bin, via reflective_near).
// Passing through means crossing it: the ray comes out into a non-obstacle cell more than
// `penetration_tolerance` before its end. A ray grazing along a wall stays inside the wall's
// cells up to its end, and a ray ending on a surface ends within the tolerance: neither counts.
//   class_of(cell) -> CellClass; reflective_near(cell, bin) -> bool.
template <typename ClassOf, typename ReflectiveNear>
double firstPassThroughDistance(const Ray& ray, const GridGeometry& geometry,
                                double penetration_tolerance, ClassOf&& class_of,
                                ReflectiveNear&& reflective_near) {
  const Eigen::Vector2d delta = ray.end - ray.origin;
  const double length = delta.norm();
  if (length <= penetration_tolerance) return -1.0;
  const Eigen::Vector2d direction = delta / length;
  const int bin = geometry.binOf(ray.angle);
  const double last_candidate = length - penetration_tolerance;
  double blocked_at = -1.0;
  GridRayTraversal traversal(ray.origin, ray.end, geometry.inverseResolution());
  while (true) {
    const CellIndex& cell = traversal.cell();
    const double along = (geometry.cellCenter(cell) - ray.origin).dot(direction);
    if (along > last_candidate) return -1.0;
    const CellClass c = class_of(cell);
    if (blocked_at < 0.0) {
      const bool blocking = c == CellClass::kGlass || c == CellClass::kMetal ||
                            (c == CellClass::kStatic && !reflective_near(cell, bin));
      if (blocking) blocked_at = along;
    } else if (!isObstacle(c)) {
      return blocked_at;  // came out on the other side
    }
    if (traversal.atEnd()) return -1.0;
    traversal.next();
  }
}

// How a ray's endpoint is judged against a map (paper Sec. VI-A): kept when the end cell, or one
// of its 8 neighbours (discretisation), is an obstacle; otherwise its evidence did not survive:
// motion (a transient object, or erased evidence when `final_map`).
template <typename ClassOf>
RayLabel labelEndpoint(const CellIndex& end_cell, bool final_map, ClassOf&& class_of) {
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
  if (motion || final_map) return RayLabel::kMotion;
  return RayLabel::kKept;  // live: not yet classified, keep it for safety
}

}  // namespace rfm
