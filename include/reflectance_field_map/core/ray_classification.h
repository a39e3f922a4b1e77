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
// first blocking cell that the ray passes through, or a negative value. A cell counts when it is
// glass, metal or static, is not itself reflective in the ray's direction (+-1 bin: the surface
// would have returned the ray there), and the ray goes on more than `penetration_tolerance`
// beyond it (a hit's own surface, or a grazing wall, is not passed through).
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
  // Only cells whose centre lies this far before the end are candidates.
  const double last_candidate = length - penetration_tolerance;
  GridRayTraversal traversal(ray.origin, ray.end, geometry.inverseResolution());
  while (true) {
    const CellIndex& cell = traversal.cell();
    const double along = (geometry.cellCenter(cell) - ray.origin).dot(direction);
    if (along > last_candidate) return -1.0;
    if (blocksRays(class_of(cell)) && !reflective_near(cell, bin)) return along;
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
