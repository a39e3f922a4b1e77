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
// One (cell, bin) update of a scan, as the inserter applies it.
struct BinUpdate {
  int32_t slot;  // window storage index
  int16_t bin;
  bool hit;
  bool operator<(const BinUpdate& o) const { return slot != o.slot ? slot < o.slot : bin < o.bin; }
};

class ScanInserter {
 public:
  // Returns the number of (cell, bin) updates applied.
  size_t insert(const std::vector<Ray>& rays, ReflectanceField& field);
  // The updates insert() would apply for `rays`, sorted by (slot, bin); the field is unchanged.
  void collectUpdates(const std::vector<Ray>& rays, const ReflectanceField& field,
                      std::vector<BinUpdate>& updates);

 private:
  template <typename Target>
  void run(const std::vector<Ray>& rays, const ReflectanceField& field, Target& target);

  std::vector<Ray> clipped_;
  std::vector<uint32_t> order_;
  std::vector<uint32_t> group_begin_;
  DeduplicatingRayInserter inserter_;
};

}  // namespace rfm
