#include "reflectance_field_map/ros/latency_histogram.h"

#include <algorithm>
#include <cmath>

namespace rfm::ros_glue {
namespace {

constexpr double kSmallestMs = 1e-3;
constexpr double kGrowth = 1.02;

}  // namespace

void LatencyHistogram::add(double ms) {
  if (!std::isfinite(ms)) return;
  const double clamped = std::max(ms, kSmallestMs);
  const int bucket =
      std::min(kBuckets - 1, static_cast<int>(std::log(clamped / kSmallestMs) / std::log(kGrowth)));
  ++buckets_[bucket];
  ++count_;
  max_ = std::max(max_, ms);
}

double LatencyHistogram::quantile(double q) const {
  if (count_ == 0) return 0.0;
  const uint64_t rank = std::max<uint64_t>(1, static_cast<uint64_t>(std::ceil(q * count_)));
  uint64_t seen = 0;
  for (int bucket = 0; bucket < kBuckets; ++bucket) {
    seen += buckets_[bucket];
    if (seen >= rank) return std::min(max_, kSmallestMs * std::pow(kGrowth, bucket + 1));
  }
  return max_;
}

}  // namespace rfm::ros_glue
