#pragma once

#include <array>
#include <cstdint>

namespace rfm::ros_glue {

// Latencies (ms) since the start, in logarithmic buckets 2 % wide from 1 us to 100 s: memory
// and cost per sample stay constant over hours, and a quantile is good to 2 %.
class LatencyHistogram {
 public:
  void add(double ms);
  // The q-quantile (0 < q <= 1) of the samples: the upper edge of its bucket; 0 when empty.
  double quantile(double q) const;
  double max() const { return max_; }
  uint64_t count() const { return count_; }

 private:
  static constexpr int kBuckets = 931;  // ln(100 s / 1 us) / ln(1.02)
  std::array<uint64_t, kBuckets> buckets_{};
  uint64_t count_ = 0;
  double max_ = 0.0;
};

}  // namespace rfm::ros_glue
