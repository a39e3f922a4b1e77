#pragma once

#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/ray_traversal.h"
#include "reflectance_field_map/core/rolling_window.h"

#include <cstdint>
#include <vector>

namespace rfm {

// Clips a ray to the window's box. A ray whose end lies outside keeps its misses up to the
// border and loses its hit. Returns false when nothing of the ray is inside.
bool clipRayToBox(const CellBox& box, double resolution, Ray& ray);

// The per-scan update rule shared by the RFM and the plain grid (Alg. 1): every ray adds misses
// to the cells it passes and a hit to its end cell; within one scan each storage slot of a
// group is updated at most once and a hit wins over a miss (hits are applied first and stamp
// their slot). Rays of one group share the slots being de-duplicated: for the RFM a group is
// one theta bin (its own slice), for the plain grid all rays form one group.
class DeduplicatingRayInserter {
 public:
  // Calls target.hit(storage_index, group) / target.miss(storage_index, group).
  // `rays` are already clipped; `group_begin[g]..group_begin[g+1]` index `order`.
  template <typename Target>
  void insert(const RollingWindow& window, double inverse_resolution, const std::vector<Ray>& rays,
              const std::vector<uint32_t>& order, const std::vector<uint32_t>& group_begin,
              Target& target);

  size_t updates() const { return updates_; }

 private:
  void prepare(size_t slots);
  uint32_t nextStamp();

  std::vector<uint32_t> stamps_;
  uint32_t stamp_ = 0;
  size_t updates_ = 0;
};

template <typename Target>
void DeduplicatingRayInserter::insert(const RollingWindow& window, double inverse_resolution,
                                      const std::vector<Ray>& rays,
                                      const std::vector<uint32_t>& order,
                                      const std::vector<uint32_t>& group_begin, Target& target) {
  const int size = window.sizeCells();
  prepare(static_cast<size_t>(size) * size);
  updates_ = 0;
  for (size_t group = 0; group + 1 < group_begin.size(); ++group) {
    const uint32_t begin = group_begin[group], end = group_begin[group + 1];
    if (begin == end) continue;
    const uint32_t stamp = nextStamp();
    for (uint32_t k = begin; k < end; ++k) {
      const Ray& ray = rays[order[k]];
      if (!ray.hit) continue;
      const int slot = window.storageIndex(
          CellIndex(static_cast<int>(std::floor(ray.end.x() * inverse_resolution)),
                    static_cast<int>(std::floor(ray.end.y() * inverse_resolution))));
      if (stamps_[slot] == stamp) continue;
      stamps_[slot] = stamp;
      target.hit(slot, static_cast<int>(group));
      ++updates_;
    }
    for (uint32_t k = begin; k < end; ++k) {
      const Ray& ray = rays[order[k]];
      GridRayTraversal traversal(ray.origin, ray.end, inverse_resolution);
      // Walk storage coordinates incrementally: the window wraps, the ray never leaves it.
      int x = window.storageCoordinate(traversal.cell().x());
      int y = window.storageCoordinate(traversal.cell().y());
      // The end cell of a hit ray holds its hit; a cleared ray misses its end cell too.
      int steps = traversal.remaining() + (ray.hit ? 0 : 1);
      while (steps-- > 0) {
        const int slot = y * size + x;
        if (stamps_[slot] != stamp) {
          stamps_[slot] = stamp;
          target.miss(slot, static_cast<int>(group));
          ++updates_;
        }
        if (traversal.atEnd()) break;
        const int axis = traversal.next();
        if (axis == 0) {
          x += traversal.step(0);
          if (x == size) x = 0;
          if (x < 0) x = size - 1;
        } else {
          y += traversal.step(1);
          if (y == size) y = 0;
          if (y < 0) y = size - 1;
        }
      }
    }
  }
}

}  // namespace rfm
