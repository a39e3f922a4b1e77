#include "reflectance_field_map/core/ray_insertion.h"

#include <algorithm>

namespace rfm {

bool clipRayLeavingBox(const Eigen::Vector2d& low, const Eigen::Vector2d& high, Ray& ray) {
  // Liang-Barsky.
  const Eigen::Vector2d delta = ray.end - ray.origin;
  double t_enter = 0.0, t_exit = 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    if (delta[axis] == 0.0) {
      if (ray.origin[axis] < low[axis] || ray.origin[axis] > high[axis]) return false;
      continue;
    }
    double t0 = (low[axis] - ray.origin[axis]) / delta[axis];
    double t1 = (high[axis] - ray.origin[axis]) / delta[axis];
    if (t0 > t1) std::swap(t0, t1);
    t_enter = std::max(t_enter, t0);
    t_exit = std::min(t_exit, t1);
    if (t_enter > t_exit) return false;
  }
  if (t_exit < 1.0) {
    ray.end = ray.origin + t_exit * delta;
    ray.hit = false;
  }
  if (t_enter > 0.0) ray.origin = ray.origin + t_enter * delta;
  return true;
}

void DeduplicatingRayInserter::prepare(size_t slots) {
  if (stamps_.size() != slots) {
    stamps_ = ZeroedHugeArray<uint16_t>(slots, PageKind::kOrdinary);
    stamp_ = 0;
  }
}

uint16_t DeduplicatingRayInserter::nextStamp() {
  if (++stamp_ == 0) {  // wrapped: old stamps could collide with the new ones
    stamps_.zeroWhereSet();
    stamp_ = 1;
  }
  return stamp_;
}

void clipRaysToRegion(const CellBox& box, double resolution, double radius,
                      std::vector<Ray>& rays) {
  size_t kept = 0;
  for (Ray& ray : rays) {
    clipRayToLength(radius, ray);
    if (clipRayToBox(box, resolution, ray)) rays[kept++] = ray;
  }
  rays.resize(kept);
}

}  // namespace rfm
