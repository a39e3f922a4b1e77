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

}  // namespace
}  // namespace rfm
