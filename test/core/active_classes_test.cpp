#include "reflectance_field_map/core/active_classes.h"

#include <gtest/gtest.h>

#include <vector>

namespace rfm {
namespace {

// A window of 4 x 4 tiles of 4 cells, at the origin, over a global map.
struct Fixture {
  Fixture() : window(/*tile_cells=*/4, /*tiles_per_side=*/4), classes(window, map, 0) {
    window.setOrigin({0, 0});
  }
  // A region of the whole window, every cell `c`.
  ClassifiedRegion regionOf(CellClass c) const {
    ClassifiedRegion region;
    region.box = window.box();
    region.classes.assign(static_cast<size_t>(region.box.width()) * region.box.height(), c);
    return region;
  }
  static void set(ClassifiedRegion& region, const CellIndex& cell, CellClass c) {
    region.classes[region.box.indexOf(cell)] = c;
  }
  RollingWindow window;
  GlobalMap2D map;
  ActiveClasses classes;
};

TEST(ActiveClasses, EnteringTilesTakeTheGlobalMapsClassesAndOutsideCellsAreTheMaps) {
  Fixture f;
  f.map.set({1, 2}, CellClass::kGlass);
  f.map.set({40, 40}, CellClass::kStatic);               // outside the window
  EXPECT_EQ(f.classes.at({1, 2}), CellClass::kUnknown);  // not entered yet
  f.classes.enter(f.window.tiles());
  EXPECT_EQ(f.classes.at({1, 2}), CellClass::kGlass);
  EXPECT_EQ(f.classes.atSlot(f.window.storageIndex({1, 2})), CellClass::kGlass);
  EXPECT_EQ(f.classes.at({40, 40}), CellClass::kStatic);
  EXPECT_EQ(f.classes.at({3, 3}), CellClass::kUnknown);
  // The clearance follows the entered classes.
  EXPECT_EQ(f.classes.clearance().at({1, 2}), 0);
  EXPECT_GT(f.classes.clearance().at({12, 12}), 1);
}

TEST(ActiveClasses, ReplaceReportsCellsThatNewlyBlockRaysOtherThanStatic) {
  Fixture f;
  ClassifiedRegion region = f.regionOf(CellClass::kFree);
  Fixture::set(region, {2, 3}, CellClass::kGlass);
  Fixture::set(region, {9, 5}, CellClass::kMetal);
  Fixture::set(region, {14, 14}, CellClass::kStatic);  // blocks, but is no new glass
  EXPECT_FALSE(f.classes.anyBlocking());
  const CellBox first = f.classes.replace(region, nullptr);
  EXPECT_TRUE(f.classes.anyBlocking());
  EXPECT_EQ(first.min, CellIndex(2, 3));
  EXPECT_EQ(first.max, CellIndex(10, 6));
  EXPECT_EQ(f.classes.at({14, 14}), CellClass::kStatic);
  EXPECT_EQ(f.classes.clearance().at({9, 5}), 0);
  // The same classes again: nothing new. Glass that was static before is not new either.
  EXPECT_TRUE(f.classes.replace(region, nullptr).empty());
  Fixture::set(region, {14, 14}, CellClass::kGlass);
  EXPECT_TRUE(f.classes.replace(region, nullptr).empty());
  // Everything gone: nothing blocks, and the clearance is open again.
  EXPECT_TRUE(f.classes.replace(f.regionOf(CellClass::kFree), nullptr).empty());
  EXPECT_FALSE(f.classes.anyBlocking());
  EXPECT_GT(f.classes.clearance().at({9, 5}), 1);
}

TEST(ActiveClasses, UnchangedTilesKeepTheirStoredClasses) {
  Fixture f;
  f.classes.replace(f.regionOf(CellClass::kFree), nullptr);
  ClassifiedRegion region = f.regionOf(CellClass::kUnknown);
  region.unchanged_tiles.assign(f.window.storageTiles(), 0);
  region.unchanged_tiles[f.window.storageTile({0, 0})] = 1;  // cells (0..3, 0..3)
  f.classes.replace(region, nullptr);
  EXPECT_EQ(f.classes.at({1, 1}), CellClass::kFree);     // skipped
  EXPECT_EQ(f.classes.at({5, 1}), CellClass::kUnknown);  // taken
}

TEST(ActiveClasses, ClearForgetsEverything) {
  Fixture f;
  ClassifiedRegion region = f.regionOf(CellClass::kFree);
  Fixture::set(region, {2, 3}, CellClass::kGlass);
  f.classes.replace(region, nullptr);
  f.classes.clear();
  EXPECT_FALSE(f.classes.anyBlocking());
  EXPECT_EQ(f.classes.at({2, 3}), CellClass::kUnknown);
  EXPECT_EQ(f.classes.clearance().at({2, 3}), 0);  // no box: nothing is known to be clear
}

}  // namespace
}  // namespace rfm
