#include "reflectance_field_map/core/scan_inserter.h"

#include <algorithm>

namespace rfm {

namespace {

struct FieldTarget {
  ReflectanceField& field;
  ReflectanceField::SliceWriter writer(int bin) { return field.sliceWriter(bin); }
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

template <typename Target>
void ScanInserter::run(const std::vector<Ray>& rays, const ReflectanceField& field,
                       Target& target) {
  const CellBox box = field.activeBox();
  const double resolution = field.geometry().resolution();
  clipped_.clear();
  for (const Ray& ray : rays) {
    Ray clipped = ray;
    if (clipRayToBox(box, resolution, clipped)) clipped_.push_back(clipped);
  }
  bucketRaysByBin(clipped_, field.geometry(), order_, group_begin_);
  inserter_.insert(field.window(), field.geometry().inverseResolution(), clipped_, order_,
                   group_begin_, target);
}

size_t ScanInserter::insert(const std::vector<Ray>& rays, ReflectanceField& field) {
  FieldTarget target{field};
  run(rays, field, target);
  return inserter_.updates();
}

void ScanInserter::collectUpdates(const std::vector<Ray>& rays, const ReflectanceField& field,
                                  std::vector<BinUpdate>& updates) {
  struct Recorder {
    std::vector<BinUpdate>& out;
    struct Writer {
      std::vector<BinUpdate>& out;
      int16_t bin;
      void hit(int slot) { out.push_back({slot, bin, true}); }
      void miss(int slot) { out.push_back({slot, bin, false}); }
    };
    Writer writer(int bin) { return {out, static_cast<int16_t>(bin)}; }
  } recorder{updates};
  updates.clear();
  run(rays, field, recorder);
  std::sort(updates.begin(), updates.end());
}

}  // namespace rfm
