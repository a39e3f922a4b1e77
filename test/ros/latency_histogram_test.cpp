#include "reflectance_field_map/ros/latency_histogram.h"

#include <gtest/gtest.h>

#include <limits>

namespace rfm::ros_glue {
namespace {

TEST(LatencyHistogram, EmptyHasNoLatency) {
  const LatencyHistogram histogram;
  EXPECT_EQ(histogram.count(), 0u);
  EXPECT_EQ(histogram.quantile(0.5), 0.0);
}

// 1..1000 ms, one sample each: the median is 500 ms and the 99th percentile 990 ms, within the
// buckets' 2 %; the maximum is exact.
TEST(LatencyHistogram, QuantilesWithinTwoPercent) {
  LatencyHistogram histogram;
  for (int ms = 1000; ms >= 1; --ms)
    histogram.add(ms);
  EXPECT_EQ(histogram.count(), 1000u);
  EXPECT_NEAR(histogram.quantile(0.5), 500.0, 10.0);
  EXPECT_NEAR(histogram.quantile(0.99), 990.0, 20.0);
  EXPECT_DOUBLE_EQ(histogram.quantile(1.0), 1000.0);
  EXPECT_DOUBLE_EQ(histogram.max(), 1000.0);
}

// Values outside the buckets land in the first or last one and do not break the quantiles;
// non-finite ones are not samples.
TEST(LatencyHistogram, ExtremesAreClampedAndNonFiniteIgnored) {
  LatencyHistogram histogram;
  histogram.add(0.0);
  histogram.add(-5.0);
  histogram.add(1e9);
  histogram.add(std::numeric_limits<double>::quiet_NaN());
  histogram.add(std::numeric_limits<double>::infinity());
  EXPECT_EQ(histogram.count(), 3u);
  EXPECT_LE(histogram.quantile(0.5), 0.0011);
  EXPECT_DOUBLE_EQ(histogram.max(), 1e9);
}

}  // namespace
}  // namespace rfm::ros_glue
