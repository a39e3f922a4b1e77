#include "reflectance_field_map/core/scan_inserter.h"

#include "reflectance_field_map/core/detail/slice_writer.h"

#include <algorithm>

namespace rfm {

namespace {

// A group is a theta bin: one scan's rays of it form one fan.
struct FieldTarget {
  static constexpr bool kOneFanPerGroup = true;
  ReflectanceField& field;
  ReflectanceField::DeferredSummaries* deferred;  // null: apply summaries at once
  detail::SliceWriter writer(int bin) { return field.sliceWriter(bin, deferred); }
};

// The same, without counting the updates (see insertScans).
struct UncountedFieldTarget : FieldTarget {
  static constexpr bool kCountsUpdates = false;
};

// Records the updates instead of applying them (not thread-safe).
struct UpdateRecorder {
  static constexpr bool kOneFanPerGroup = true;  // as FieldTarget
  std::vector<BinUpdate>& out;
  struct Writer {
    std::vector<BinUpdate>& out;
    int16_t bin;
    void hit(int slot) { out.push_back({slot, bin, true}); }
    void miss(int slot) { out.push_back({slot, bin, false}); }
  };
  Writer writer(int bin) { return {out, static_cast<int16_t>(bin)}; }
};

}  // namespace

void bucketRaysByBin(const std::vector<Ray>& rays, const GridGeometry& geometry,
                     std::vector<uint32_t>& order, std::vector<uint32_t>& group_begin) {
  const int bins = geometry.thetaBins();
  group_begin.assign(bins + 1, 0);
  std::vector<int> ray_bins(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    ray_bins[i] = geometry.binOf(rays[i].angle);
    ++group_begin[ray_bins[i] + 1];
  }
  for (int b = 0; b < bins; ++b)
    group_begin[b + 1] += group_begin[b];
  order.resize(rays.size());
  std::vector<uint32_t> next(group_begin.begin(), group_begin.end() - 1);
  for (size_t i = 0; i < rays.size(); ++i)
    order[next[ray_bins[i]]++] = static_cast<uint32_t>(i);
}

ScanInserter::ScanInserter(int threads)
    : ScanInserter(threads > 1 ? std::make_shared<ParallelRunner>(threads) : nullptr) {}

namespace {

// Lists per thread's deferred summary changes: as many as threads, rounded down to a power of two.
int summaryParts(const ParallelRunner* runner) {
  int parts = 1;
  while (runner && parts * 2 <= runner->threads() &&
         parts * 2 <= ReflectanceField::DeferredSummaries::kMaxParts) {
    parts *= 2;
  }
  return parts;
}

}  // namespace

ScanInserter::ScanInserter(std::shared_ptr<ParallelRunner> runner)
    : inserters_(runner ? runner->threads() : 1),
      deferred_(inserters_.size(), ReflectanceField::DeferredSummaries(summaryParts(runner.get()))),
      runner_(std::move(runner)) {}

ScanInserter::~ScanInserter() = default;

void ScanInserter::prepare(const std::vector<Ray>& rays, const ReflectanceField& field,
                           PreparedScan& prepared) {
  const CellBox box = field.activeBox();
  const double resolution = field.geometry().resolution();
  prepared.clipped.clear();
  for (const Ray& ray : rays) {
    Ray clipped = ray;
    if (clipRayToBox(box, resolution, clipped)) prepared.clipped.push_back(clipped);
  }
  bucketRaysByBin(prepared.clipped, field.geometry(), prepared.order, prepared.group_begin);
}

template <typename InsertBins>
size_t ScanInserter::forBinChunks(int bins, bool parallel, InsertBins&& insert_bins) {
  // A chunk of bins at a time, also on one thread: for several scans, a chunk's few slices stay
  // in cache while every scan's rays go in, where all 180 would not.
  constexpr size_t kChunkBins = 6;
  const size_t chunks = (bins + kChunkBins - 1) / kChunkBins;
  if (!parallel || !runner_ || runner_->threads() == 1) {
    size_t updates = 0;
    for (size_t chunk = 0; chunk < chunks; ++chunk)
      updates += insert_bins(chunk * kChunkBins, (chunk + 1) * kChunkBins, -1);
    return updates;
  }
  // Threads take chunks as they become free: rays differ in length and overlap, so a static
  // split would leave one thread waiting for the other. Each thread has its own stamps.
  std::vector<size_t> thread_updates(runner_->threads(), 0);
  parallelFor(runner_.get(), chunks, 1, [&](size_t chunk, int thread) {
    thread_updates[thread] += insert_bins(chunk * kChunkBins, (chunk + 1) * kChunkBins, thread);
  });
  size_t updates = 0;
  for (size_t part : thread_updates)
    updates += part;
  return updates;
}

template <typename MakeTarget>
void ScanInserter::run(const std::vector<Ray>& rays, const ReflectanceField& field,
                       MakeTarget&& make_target, bool parallel) {
  prepare(rays, field, single_);
  // Too few rays are not worth waking a helper for.
  constexpr size_t kMinRaysToSplit = 64;
  parallel &= single_.clipped.size() >= kMinRaysToSplit;
  const double inverse_resolution = field.geometry().inverseResolution();
  updates_ = forBinChunks(
      field.geometry().thetaBins(), parallel, [&](size_t first_bin, size_t end_bin, int part) {
        auto&& target = make_target(part);
        DeduplicatingRayInserter& inserter = inserters_[std::max(part, 0)];
        inserter.insert(field.window(), inverse_resolution, single_.clipped, single_.order,
                        single_.group_begin, target, first_bin, end_bin);
        return inserter.updates();
      });
}

size_t ScanInserter::insert(const std::vector<Ray>& rays, ReflectanceField& field, bool share) {
  for (ReflectanceField::DeferredSummaries& deferred : deferred_)
    deferred.clear();
  // Part -1 is the caller alone; parts running side by side defer their summary changes.
  run(
      rays, field,
      [&](int part) {
        return FieldTarget{field, part < 0 ? nullptr : &deferred_[part]};
      },
      share);
  field.applySummaryChanges(deferred_, share ? runner_.get() : nullptr);
  return updates_;
}

void ScanInserter::insertScans(const std::vector<std::vector<Ray>>& scans, size_t count,
                               ReflectanceField& field) {
  if (batch_.size() < count) batch_.resize(count);
  parallelFor(runner_.get(), count, 1, [&](size_t s, int) {
    bucketRaysByBin(scans[s], field.geometry(), batch_[s].order, batch_[s].group_begin);
  });
  for (ReflectanceField::DeferredSummaries& deferred : deferred_)
    deferred.clear();
  const double inverse_resolution = field.geometry().inverseResolution();
  // Each bin sees the scans in their order, so its filters take the same updates as scan by scan.
  forBinChunks(field.geometry().thetaBins(), true, [&](size_t first_bin, size_t end_bin, int part) {
    UncountedFieldTarget target{{field, part < 0 ? nullptr : &deferred_[part]}};
    DeduplicatingRayInserter& inserter = inserters_[std::max(part, 0)];
    for (size_t s = 0; s < count; ++s) {
      inserter.insert(field.window(), inverse_resolution, scans[s], batch_[s].order,
                      batch_[s].group_begin, target, first_bin, end_bin);
    }
    return size_t{0};
  });
  field.applySummaryChanges(deferred_, runner_.get());
}

void ScanInserter::collectUpdates(const std::vector<Ray>& rays, const ReflectanceField& field,
                                  std::vector<BinUpdate>& updates) {
  UpdateRecorder recorder{updates};
  updates.clear();
  // On the caller alone, so the bins come in ascending order.
  run(
      rays, field, [&](int) -> UpdateRecorder& { return recorder; }, /*parallel=*/false);
}

}  // namespace rfm
