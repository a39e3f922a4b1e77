#include "reflectance_field_map/core/batch_processor.h"

#include "scenario.h"

#include <gtest/gtest.h>

#include <sstream>

namespace rfm {
namespace {

using testing::driveBy;
using testing::runScenario;
using testing::SyntheticWorld;

SyntheticWorld room() {
  SyntheticWorld world;
  world.addWall({-4.0, -3.0}, {4.0, -3.0});
  world.addWall({4.0, -3.0}, {4.0, 3.0});
  world.addWall({4.0, 3.0}, {-4.0, 3.0});
  world.addWall({-4.0, 3.0}, {-4.0, -3.0});
  world.addFramedPane({-3.0, 0.0}, {0.0, 0.0});  // parallel to the robot's paths
  return world;
}

TEST(Mapper, MalformedScansAreRejectedAndChangeNothing) {
  Mapper mapper(MapperOptions{});
  TimedScan scan = room().timedScan({{0.0, 0.0}, 0.0});
  scan.scan.ranges.pop_back();
  scan.scan.ranges.pop_back();
  scan.scan.ranges.pop_back();
  const ScanUpdate update = mapper.addScan(scan);
  EXPECT_FALSE(update.error.empty());
  EXPECT_EQ(mapper.stats().scans_processed, 0u);
  EXPECT_EQ(update.labels.size(), scan.scan.ranges.size());
}

TEST(Mapper, NanAndInfiniteRangesAreHandled) {
  Mapper mapper(MapperOptions{});
  TimedScan scan = room().timedScan({{0.0, 0.0}, 0.0});
  scan.scan.ranges[0] = std::nanf("");
  scan.scan.ranges[1] = -std::numeric_limits<float>::infinity();
  scan.scan.ranges[2] = std::numeric_limits<float>::infinity();
  scan.scan.ranges[3] = 0.01f;
  const ScanUpdate update = mapper.addScan(scan);
  EXPECT_TRUE(update.error.empty());
  EXPECT_EQ(update.labels[0], RayLabel::kNoReturn);
  EXPECT_EQ(update.labels[1], RayLabel::kNoReturn);
  EXPECT_EQ(update.labels[3], RayLabel::kNoReturn);
  EXPECT_EQ(update.labels[4], RayLabel::kKept);
}

TEST(Mapper, SaveLoadRoundTripsTheMapAndTheField) {
  SyntheticWorld world = room();
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveBy({-2.0, 1.0}, {2.0, 1.0}, 0.0));
  std::stringstream state;
  mapper.save(state);

  Mapper restored(testing::scenarioOptions());
  ASSERT_TRUE(restored.load(state));
  std::vector<CellClass> a, b;
  mapper.map().extract(mapper.map().bounds(), a);
  restored.map().extract(mapper.map().bounds(), b);
  EXPECT_EQ(a, b);
  EXPECT_GT(std::count(a.begin(), a.end(), CellClass::kGlass), 10);
  // The field comes back too: continue mapping and classify again, same result.
  const TimedScan next = world.timedScan({{2.0, 1.0}, 0.0});
  mapper.addScan(next);
  restored.addScan(next);
  const CellIndex wall = mapper.field().geometry().cellOf({4.0 + 1e-3, 0.5});
  for (int bin = 0; bin < 180; ++bin)
    ASSERT_EQ(mapper.field().value(wall, bin), restored.field().value(wall, bin));
  mapper.removeMotion();
  restored.removeMotion();
  mapper.map().extract(mapper.map().bounds(), a);
  restored.map().extract(mapper.map().bounds(), b);
  EXPECT_EQ(a, b);

  std::stringstream garbage("garbage");
  EXPECT_FALSE(restored.load(garbage));
}

TEST(Mapper, ResetForgetsEverything) {
  SyntheticWorld world = room();
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveBy({-2.0, 1.0}, {2.0, 1.0}, 0.0));
  EXPECT_GT(mapper.map().tileCount(), 0u);
  mapper.reset();
  EXPECT_EQ(mapper.map().tileCount(), 0u);
  EXPECT_EQ(mapper.stats().scans_processed, 0u);
}

TEST(Mapper, GlobalMapKeepsWhatTheActiveRegionLeftBehind) {
  SyntheticWorld world;
  world.addWall({0.0, 2.0}, {40.0, 2.0});
  world.addWall({0.0, -2.0}, {40.0, -2.0});
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveBy({1.0, 0.0}, {39.0, 0.0}, 0.0));
  const GridGeometry& g = mapper.field().geometry();
  // The start of the corridor left the active region long ago but stays in the map.
  EXPECT_FALSE(mapper.field().inActiveRegion(g.cellOf({3.0, 2.0})));
  EXPECT_TRUE(isObstacle(mapper.map().get(g.cellOf({3.0, 2.0 + 1e-3}))) ||
              isObstacle(mapper.map().get(g.cellOf({3.0, 2.0 - 1e-3}))));
  EXPECT_EQ(mapper.map().get(g.cellOf({3.0, 0.0})), CellClass::kFree);
  EXPECT_GT(mapper.stats().archived_bytes, 0u);
}

TEST(BatchProcessor, PlainGridBaselineErasesGlassThatTheRfmKeeps) {
  SyntheticWorld world = room();
  std::vector<TimedScan> scans;
  for (const auto& step : driveBy({-2.5, 1.5}, {2.5, 1.5}, 0.0)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  for (const auto& step : driveBy({2.5, -1.5}, {-2.5, -1.5}, kPi)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  const BatchResult baseline = processBatch(scans, MapperOptions{}, BatchMode::kPlainGrid);
  const BatchResult full = processBatch(scans, MapperOptions{}, BatchMode::kFull);
  ASSERT_EQ(baseline.labels.size(), scans.size());
  ASSERT_EQ(full.labels.size(), scans.size());
  EXPECT_EQ(full.labels[0].size(), scans[0].scan.ranges.size());
  const GridGeometry g(0.05, 180);
  auto pane_kept = [&](const GlobalMap2D& map) {
    int kept = 0, total = 0;
    for (double x = -2.8; x <= -0.2; x += 0.05, ++total) {
      kept += isObstacle(map.get(g.cellOf({x, 1e-3}))) || isObstacle(map.get(g.cellOf({x, -1e-3})));
    }
    return static_cast<double>(kept) / total;
  };
  EXPECT_GT(pane_kept(full.map), 0.9);
  EXPECT_LT(pane_kept(baseline.map), 0.5);
}

}  // namespace
}  // namespace rfm
