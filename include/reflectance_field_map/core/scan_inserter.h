#pragma once

#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/ray_insertion.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <vector>

namespace rfm {

// Counting sort of rays by theta bin: rays of bin b are order[group_begin[b] .. group_begin[b+1]).
void bucketRaysByBin(const std::vector<Ray>& rays, const GridGeometry& geometry,
                     std::vector<uint32_t>& order, std::vector<uint32_t>& group_begin);

// Adds one scan's rays to the reflectance field (Alg. 1). Each ray updates only the theta
// slice of its own direction; rays are bucketed by bin (counting sort) so one bin's rays are
// de-duplicated together. Rays are clipped to the active window first.
class ScanInserter {
 public:
  // Returns the number of (cell, bin) updates applied.
  size_t insert(const std::vector<Ray>& rays, ReflectanceField& field);

 private:
  std::vector<Ray> clipped_;
  std::vector<uint32_t> order_;
  std::vector<uint32_t> group_begin_;
  DeduplicatingRayInserter inserter_;
};

}  // namespace rfm
