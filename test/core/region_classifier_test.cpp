#include "reflectance_field_map/core/region_classifier.h"

#include "test_fields.h"

#include <gtest/gtest.h>

namespace rfm {
namespace {

// A 2 m field at the origin with a cell reflective over 20 bins (a pillar's face) and a cell
// only missed (free space), and glass completion off.
class RegionClassifierTest : public ::testing::Test {
 protected:
  RegionClassifierTest()
      : field_(testing::centredField(2.0)),
        rule_(OccupancyOptions(), field_.geometry().binWidth()),
        completion_off_(field_.geometry(), 0.0),
        pillar_(field_.geometry().cellOf({0.525, 0.525})),
        free_(field_.geometry().cellOf({-1.025, -1.025})) {
    for (int bin = 0; bin < 20; ++bin) {
      for (int i = 0; i < 3; ++i)
        field_.applyHit(pillar_, bin);
    }
    field_.applyMiss(free_, 10);
  }

  ReflectanceField field_;
  OccupancyRule rule_;
  GlassCompletion completion_off_;
  AnchorHistory history_{field_};
  GlobalMap2D map_;
  const CellIndex pillar_;
  const CellIndex free_;
};

TEST_F(RegionClassifierTest, WithoutMotionRemovalEveryCellFollowsEquationFive) {
  RegionClassifier classifier(rule_, /*motion=*/nullptr, completion_off_);
  const MotionRemovalCounts counts = classifier.classify(field_, history_, map_, nullptr);
  EXPECT_EQ(counts.static_cells, 1u);
  EXPECT_EQ(counts.free_cells, 1u);
  EXPECT_EQ(classifier.region().box.min, field_.activeBox().min);
  EXPECT_EQ(classifier.region().box.max, field_.activeBox().max);
  EXPECT_EQ(classifier.region().at(pillar_), CellClass::kOccupied);
  EXPECT_EQ(classifier.region().at(free_), CellClass::kFree);
  EXPECT_TRUE(classifier.region().unchanged_tiles.empty());

  map_.set(free_, CellClass::kStatic);  // whatever the map held is overwritten
  classifier.writeTo(field_.window(), map_);
  EXPECT_EQ(map_.get(pillar_), CellClass::kOccupied);
  EXPECT_EQ(map_.get(free_), CellClass::kFree);
}

TEST_F(RegionClassifierTest, TilesMotionRemovalReusedAreNotWrittenAgain) {
  MotionRemover motion(rule_);
  RegionClassifier classifier(rule_, &motion, completion_off_);
  classifier.classify(field_, history_, map_, nullptr);
  classifier.writeTo(field_.window(), map_);
  ASSERT_EQ(map_.get(free_), CellClass::kFree);

  // Nothing changed in the free cell's tile: the second pass leaves the map's copy alone, so a
  // mark put there in between survives.
  map_.set(free_, CellClass::kStatic);
  classifier.classify(field_, history_, map_, nullptr);
  const RollingWindow& window = field_.window();
  EXPECT_TRUE(classifier.region().unchanged_tiles[window.storageTile(window.tileOf(free_))]);
  classifier.writeTo(field_.window(), map_);
  EXPECT_EQ(map_.get(free_), CellClass::kStatic);

  // New evidence in the tile: it is classified and written again.
  field_.applyMiss(free_, 70);
  classifier.classify(field_, history_, map_, nullptr);
  EXPECT_FALSE(classifier.region().unchanged_tiles[window.storageTile(window.tileOf(free_))]);
  classifier.writeTo(field_.window(), map_);
  EXPECT_EQ(map_.get(free_), CellClass::kFree);
}

// Two lines of cells between widely visible frames, each glass by motion removal's rules (anchored
// by a frame, seen through from elsewhere): one returns along its normal, a pane; the other only
// 40 deg off it, as the image of a wall in a mirror does: static.
TEST(RegionClassifier, GlassThatNeverReturnedNearItsNormalIsDrawnStatic) {
  ReflectanceField field = testing::centredField(2.0);
  const GridGeometry& geometry = field.geometry();  // 2 deg bins
  auto line_of = [&](double y, int first_bin, int last_bin) {
    for (int k = -10; k <= 10; ++k) {
      const CellIndex cell = geometry.cellOf({0.05 * k + 0.025, y});
      const bool frame = k == -10 || k == 10;
      for (int bin = 0; bin < geometry.thetaBins(); ++bin) {
        const bool reflects =
            frame ? (bin >= 20 && bin < 70) : (bin >= first_bin && bin <= last_bin);
        for (int i = 0; i < 4; ++i)
          reflects ? field.applyHit(cell, bin) : field.applyMiss(cell, bin);
      }
    }
  };
  line_of(-0.475, 44, 45);  // faced: 88-92 deg, the line's normal
  line_of(0.525, 24, 25);   // 48-52 deg only
  const OccupancyRule rule(OccupancyOptions(), geometry.binWidth());
  MotionRemover motion(rule);
  RegionClassifier classifier(rule, &motion, GlassCompletion(geometry, 0.0));
  AnchorHistory history(field);
  GlobalMap2D map;
  classifier.classify(field, history, map, nullptr);
  for (int k = -8; k <= 8; ++k) {
    EXPECT_EQ(classifier.region().at(geometry.cellOf({0.05 * k + 0.025, -0.475})),
              CellClass::kGlass)
        << k;
    EXPECT_EQ(classifier.region().at(geometry.cellOf({0.05 * k + 0.025, 0.525})),
              CellClass::kStatic)
        << k;
  }
}

}  // namespace
}  // namespace rfm
