#pragma once

#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/ray_insertion.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <memory>
#include <vector>

namespace rfm {

// Counting sort of rays by theta bin: rays of bin b are order[group_begin[b] .. group_begin[b+1]).
void bucketRaysByBin(const std::vector<Ray>& rays, const GridGeometry& geometry,
                     std::vector<uint32_t>& order, std::vector<uint32_t>& group_begin);

// One (cell, bin) update of a scan, as the inserter applies it.
struct BinUpdate {
  int32_t slot;  // window storage index
  int16_t bin;
  bool hit;
  bool operator<(const BinUpdate& o) const { return slot != o.slot ? slot < o.slot : bin < o.bin; }
  bool operator==(const BinUpdate& o) const {
    return slot == o.slot && bin == o.bin && hit == o.hit;
  }
};

// Adds one scan's rays to the reflectance field (Alg. 1). Each ray updates only the theta
// slice of its own direction; rays are bucketed by bin (counting sort) so one bin's rays are
// de-duplicated together. Rays are clipped to the active window first.
class ScanInserter {
 public:
  // With `threads` > 1 the bins of a scan are shared out between that many threads (the caller
  // and helpers) in small chunks; each bin's slice is written by one thread only.
  explicit ScanInserter(int threads = 1);
  // The same, on a runner shared with other work of the caller (null: the caller alone).
  explicit ScanInserter(std::shared_ptr<ParallelRunner> runner);
  ~ScanInserter();
  ScanInserter(const ScanInserter&) = delete;
  ScanInserter& operator=(const ScanInserter&) = delete;

  // Returns the number of (cell, bin) updates applied. share = false: the caller alone, the
  // runner's helpers left asleep (the field comes out the same).
  size_t insert(const std::vector<Ray>& rays, ReflectanceField& field, bool share = true);
  // The same as insert() on scans[0, count) in turn (the window must stay put), but theta bin by
  // theta bin across the scans: a bin's slice is written for all of them while it is in cache.
  // Their rays must lie inside the window already (as Mapper::clipToActiveRegion leaves them):
  // they are not clipped or copied again. The updates are not counted: only a live scan's
  // statistics report them, and counting every cell visit costs the batch 1 % of its instructions.
  void insertScans(const std::vector<std::vector<Ray>>& scans, size_t count,
                   ReflectanceField& field);
  // The updates insert() would apply for `rays`, grouped by theta bin in ascending order (a slot
  // at most once per bin, in the sweep's order within it); the field is unchanged.
  void collectUpdates(const std::vector<Ray>& rays, const ReflectanceField& field,
                      std::vector<BinUpdate>& updates);

  // Rays bucketed by theta bin (bucketRaysByBin): bin b's rays are
  // rays[order[group_begin[b] .. group_begin[b + 1])], as the inserter sweeps them.
  struct BinBuckets {
    std::vector<uint32_t> order;
    std::vector<uint32_t> group_begin;
  };
  // A scan's rays clipped to the window, and their buckets.
  struct PreparedScan : BinBuckets {
    std::vector<Ray> clipped;
  };
  static void prepare(const std::vector<Ray>& rays, const ReflectanceField& field,
                      PreparedScan& prepared);

 private:
  // make_target(part) gives the target of one thread's part (-1: the caller alone).
  template <typename MakeTarget>
  void run(const std::vector<Ray>& rays, const ReflectanceField& field, MakeTarget&& make_target,
           bool parallel);

  // Runs insert_bins(first_bin, end_bin, part) over all bins in chunks: on the runner's threads
  // (part = thread), or in turn by the caller (part -1). Returns the sum of its results.
  template <typename InsertBins>
  size_t forBinChunks(int bins, bool parallel, InsertBins&& insert_bins);

  PreparedScan single_;
  std::vector<BinBuckets> batch_;                    // insertScans': its scans' rays go in as given
  std::vector<DeduplicatingRayInserter> inserters_;  // one per thread: each has its own stamps
  // Per thread, each in its own cache lines (threads append to them side by side).
  std::vector<ReflectanceField::DeferredSummaries> deferred_;
  std::shared_ptr<ParallelRunner> runner_;
  size_t updates_ = 0;
};

}  // namespace rfm
