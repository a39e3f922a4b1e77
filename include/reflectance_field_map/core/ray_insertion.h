#pragma once

#include "reflectance_field_map/core/detail/compiler.h"
#include "reflectance_field_map/core/fan_traversal.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/ray_traversal.h"
#include "reflectance_field_map/core/rolling_window.h"
#include "reflectance_field_map/core/zeroed_huge_array.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <type_traits>
#include <vector>

namespace rfm {

// clipRayToBox's clip proper, for a ray not inside [low, high] (the box shrunk by its margin).
bool clipRayLeavingBox(const Eigen::Vector2d& low, const Eigen::Vector2d& high, Ray& ray);

// Clips a ray to the window's box. A ray whose end lies outside keeps its misses up to the
// border and loses its hit. Returns false when nothing of the ray is inside. Inline: every ray
// of every pass is tested, and nearly all lie inside.
inline bool clipRayToBox(const CellBox& box, double resolution, Ray& ray) {
  // Against the box shrunk by a hair, so clipped points stay in its cells. In scalars: with
  // Eigen's, the compiler stopped inlining the test.
  const double margin = 1e-6 * resolution;
  const double low_x = box.min.x() * resolution + margin, low_y = box.min.y() * resolution + margin;
  const double high_x = box.max.x() * resolution - margin;
  const double high_y = box.max.y() * resolution - margin;
  const bool inside = ray.origin.x() >= low_x && ray.origin.x() <= high_x &&
                      ray.origin.y() >= low_y && ray.origin.y() <= high_y && ray.end.x() >= low_x &&
                      ray.end.x() <= high_x && ray.end.y() >= low_y && ray.end.y() <= high_y;
  return inside || clipRayLeavingBox({low_x, low_y}, {high_x, high_y}, ray);
}

// Shortens a ray longer than `max_length` to that length; it then loses its hit. Inline: every
// ray of every pass goes through it.
inline void clipRayToLength(double max_length, Ray& ray) {
  const Eigen::Vector2d delta = ray.end - ray.origin;
  // Most rays are shorter by far: no square root for them. The margin keeps the decision the
  // square root's wherever the squares' rounding could tell otherwise.
  if (delta.squaredNorm() < max_length * max_length * (1.0 - 1e-9)) return;
  const double length = delta.norm();
  if (length > max_length) {
    ray.end = ray.origin + delta * (max_length / length);
    ray.hit = false;
  }
}

// Limits rays to `radius` around their origin (evidence only within the active-region radius of
// the sensor, live and in batch alike) and to `box` (the walks after need rays inside it);
// rays with nothing inside are dropped, and a ray cut short loses its hit.
void clipRaysToRegion(const CellBox& box, double resolution, double radius, std::vector<Ray>& rays);

// The per-scan update rule shared by the RFM and the plain grid (Alg. 1): every ray adds misses
// to the cells it passes and a hit to its end cell; within one scan each storage slot of a
// group is updated at most once and a hit wins over a miss (hits are applied first and stamp
// their slot). Rays of one group share the slots being de-duplicated: for the RFM a group is
// one theta bin (its own slice), for the plain grid all rays form one group.
// Aligned to a cache line: inserters working side by side (one per thread) must not share one.
class alignas(64) DeduplicatingRayInserter {
 public:
  // For each group g, `target.writer(g)` returns an object with hit(slot) and miss(slot).
  // A target whose groups are each one scan's rays of one theta bin, which form one fan,
  // declares `static constexpr bool kOneFanPerGroup = true`: those sweeps then skip the stamps
  // where they can (visitCellsOfRays). The plain grid's one group is a whole scan.
  // updates() counts the updates applied, unless the target declares
  // `static constexpr bool kCountsUpdates = false` (then it is 0).
  // `rays` are already clipped; `group_begin[g]..group_begin[g+1]` index `order`. Only groups
  // in [first_group, end_group) are inserted (all by default): inserters with their own stamps
  // may take disjoint group ranges concurrently.
  template <typename Target>
  void insert(const RollingWindow& window, double inverse_resolution, const std::vector<Ray>& rays,
              const std::vector<uint32_t>& order, const std::vector<uint32_t>& group_begin,
              Target& target, size_t first_group = 0, size_t end_group = SIZE_MAX);

  size_t updates() const { return updates_; }

 private:
  void prepare(size_t slots);
  uint16_t nextStamp();

  // Two bytes per slot: the stamps are cleared every 65535 groups. One byte would clear them
  // every 255 groups (about two scans): for the batch's window of the whole recording (590 k
  // slots on curved glass), 3 % of its instructions.
  ZeroedHugeArray<uint16_t> stamps_;  // zero where no ray went: those pages stay unmapped
  uint16_t stamp_ = 0;
  size_t updates_ = 0;
};

namespace detail {

// Adds a miss to each slot not yet stamped, counting them if kCount. Holds everything by value:
// byte stores may alias any memory, so state reached through pointers or references would be
// reloaded every cell.
template <typename Writer, bool kCount>
struct MissWriter {
  uint16_t* stamps;
  uint16_t stamp;
  Writer writer;
  size_t updates = 0;
  RFM_ALWAYS_INLINE void operator()(int slot) {
    if (stamps[slot] != stamp) {
      stamps[slot] = stamp;
      writer.miss(slot);
      if constexpr (kCount) ++updates;
    }
  }
};

// For groups that are one fan of rays (Target::kOneFanPerGroup): cells the sweep visits once
// and that end no ray (visitCellsOfRays) take their miss without a stamp.
template <typename Writer, bool kCount>
struct FanMissWriter : MissWriter<Writer, kCount> {
  RFM_ALWAYS_INLINE void once(int slot) {
    this->writer.miss(slot);
    if constexpr (kCount) ++this->updates;
  }
};

template <typename Target, typename = void>
struct OneFanPerGroup : std::false_type {};
template <typename Target>
struct OneFanPerGroup<Target, std::void_t<decltype(Target::kOneFanPerGroup)>>
    : std::bool_constant<Target::kOneFanPerGroup> {};

template <typename Target, typename = void>
struct CountsUpdates : std::true_type {};
template <typename Target>
struct CountsUpdates<Target, std::void_t<decltype(Target::kCountsUpdates)>>
    : std::bool_constant<Target::kCountsUpdates> {};

}  // namespace detail

template <typename Target>
void DeduplicatingRayInserter::insert(const RollingWindow& window, double inverse_resolution,
                                      const std::vector<Ray>& rays,
                                      const std::vector<uint32_t>& order,
                                      const std::vector<uint32_t>& group_begin, Target& target,
                                      size_t first_group, size_t end_group) {
  const int size = window.sizeCells();
  prepare(static_cast<size_t>(size) * size);
  constexpr bool kCount = detail::CountsUpdates<Target>::value;
  size_t updates = 0;
  uint16_t* const stamps = stamps_.data();
  end_group = std::min(end_group, group_begin.size() - 1);
  for (size_t group = first_group; group < end_group; ++group) {
    const uint32_t begin = group_begin[group], end = group_begin[group + 1];
    if (begin == end) continue;
    const uint16_t stamp = nextStamp();
    auto writer = target.writer(static_cast<int>(group));
    for (uint32_t k = begin; k < end; ++k) {
      const Ray& ray = rays[order[k]];
      if (!ray.hit) continue;
      const int slot = window.storageIndex(CellIndex(floorToInt(ray.end.x() * inverse_resolution),
                                                     floorToInt(ray.end.y() * inverse_resolution)));
      if (stamps[slot] == stamp) continue;
      stamps[slot] = stamp;
      writer.hit(slot);
      if constexpr (kCount) ++updates;
    }
    // Misses on every cell of the group's rays. A hit ray's end cell holds its hit: stamped
    // above, so the sweep (which covers end cells) passes over it.
    using Misses = std::conditional_t<detail::OneFanPerGroup<Target>::value,
                                      detail::FanMissWriter<decltype(writer), kCount>,
                                      detail::MissWriter<decltype(writer), kCount>>;
    const Misses misses = visitCellsOfRays(rays, &order[begin], end - begin, inverse_resolution,
                                           window, Misses{stamps, stamp, writer});
    updates += misses.updates;
  }
  updates_ = updates;
}

}  // namespace rfm
