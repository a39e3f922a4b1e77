#include "reflectance_field_map/core/occupancy.h"

#include "test_fields.h"

#include <gtest/gtest.h>

namespace rfm {
namespace {

const double kDeg = kPi / 180.0;

TEST(OccupancyRule, AlphaCountsReflectiveAngle) {
  OccupancyOptions options;
  options.alpha = 1.0 * kDeg;
  const OccupancyRule one_degree(options, 2.0 * kDeg);
  EXPECT_FALSE(one_degree.isOccupied(0));
  EXPECT_TRUE(one_degree.isOccupied(1));  // 2 deg > 1 deg
  options.alpha = 5.0 * kDeg;
  const OccupancyRule five_degrees(options, 2.0 * kDeg);
  EXPECT_FALSE(five_degrees.isOccupied(2));  // 4 deg
  EXPECT_TRUE(five_degrees.isOccupied(3));   // 6 deg
  EXPECT_EQ(five_degrees.classify(2, 10), CellClass::kFree);
  EXPECT_EQ(five_degrees.classify(2, 0), CellClass::kUnknown);
  EXPECT_EQ(five_degrees.classify(3, 10), CellClass::kOccupied);
}

ReflectanceField fieldWithHits(int bins_hit, int hits_per_bin, int bins_missed) {
  ReflectanceField field = testing::centredField(2.0);
  for (int b = 0; b < bins_hit; ++b) {
    for (int k = 0; k < hits_per_bin; ++k)
      field.applyHit({0, 0}, b);
  }
  for (int b = 0; b < bins_missed; ++b) {
    for (int k = 0; k < 10; ++k)
      field.applyMiss({0, 0}, 179 - b);
  }
  return field;
}

TEST(OccupancyRule, BetaSeparatesWidelyVisibleFromNarrowLobes) {
  const OccupancyRule rule(OccupancyOptions(), 2.0 * kDeg);  // beta = 30
  // A wall edge or frame seen saturated over 60 deg (30 bins): widely visible.
  EXPECT_TRUE(rule.isWidelyVisible(fieldWithHits(30, 10, 60), {0, 0}));
  // A person standing still while the robot drove past, seen over 40 deg: not.
  EXPECT_FALSE(rule.isWidelyVisible(fieldWithHits(20, 10, 60), {0, 0}));
  // A glass face seen near its normal (3 bins) and missed from 90 other bins: not.
  EXPECT_FALSE(rule.isWidelyVisible(fieldWithHits(3, 10, 90), {0, 0}));
  // A brief, unsaturated glimpse of many bins (one hit each) is not widely visible either.
  EXPECT_FALSE(rule.isWidelyVisible(fieldWithHits(20, 1, 100), {0, 0}));
  // An unobserved cell sums to 2*pi < beta.
  EXPECT_FALSE(rule.isWidelyVisible(fieldWithHits(0, 0, 0), {0, 0}));
}

TEST(OccupancyRule, BatchBetaLeavesAPersonWhoStoodStillOut) {
  OccupancyOptions batch;
  batch.beta = BatchOptions().batch_beta;  // as processBatch classifies: 40
  const OccupancyRule rule(batch, 2.0 * kDeg);
  // The threshold: 31 saturated bins with the others unobserved, 35 with the others missed.
  EXPECT_FALSE(rule.isWidelyVisible(fieldWithHits(30, 10, 0), {0, 0}));
  EXPECT_TRUE(rule.isWidelyVisible(fieldWithHits(31, 10, 0), {0, 0}));
  EXPECT_FALSE(rule.isWidelyVisible(fieldWithHits(34, 10, 146), {0, 0}));
  EXPECT_TRUE(rule.isWidelyVisible(fieldWithHits(35, 10, 145), {0, 0}));
  // A person standing still while the robot drove past, seen over 48 deg (the atrium's, 4 s in
  // a doorway 3.3 m away): widely visible at the live beta, not at the batch's.
  const ReflectanceField person = fieldWithHits(24, 10, 30);
  EXPECT_FALSE(rule.isWidelyVisible(person, {0, 0}));
  EXPECT_TRUE(OccupancyRule(OccupancyOptions(), 2.0 * kDeg).isWidelyVisible(person, {0, 0}));
}

TEST(OccupancyRule, MetalNeedsAWideLobe) {
  const OccupancyRule rule(OccupancyOptions(), 2.0 * kDeg);  // 16 deg
  EXPECT_FALSE(rule.isMetalLobe(5));  // glass returning within +-5 deg of its normal
  EXPECT_FALSE(rule.isMetalLobe(7));
  EXPECT_TRUE(rule.isMetalLobe(8));
}

TEST(CellClass, OccupancyValues) {
  EXPECT_EQ(occupancyValue(CellClass::kUnknown), -1);
  EXPECT_EQ(occupancyValue(CellClass::kFree), 0);
  EXPECT_EQ(occupancyValue(CellClass::kMotion), 0);
  EXPECT_EQ(occupancyValue(CellClass::kStatic), 100);
  EXPECT_EQ(occupancyValue(CellClass::kGlass), 100);
  EXPECT_EQ(occupancyValue(CellClass::kMetal), 100);
}

}  // namespace
}  // namespace rfm
