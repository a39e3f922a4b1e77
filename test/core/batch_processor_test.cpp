#include "reflectance_field_map/core/batch_processor.h"

#include "reflectance_field_map/core/detail/glass_passes.h"

#include "scenario.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfm {
namespace {

using testing::countLabels;
using testing::driveBy;
using testing::paneWithWallBehind;
using testing::roomWithPane;
using testing::SyntheticWorld;

TEST(BatchProcessor, PlainGridBaselineErasesGlassThatTheRfmKeeps) {
  SyntheticWorld world = roomWithPane();
  std::vector<TimedScan> scans;
  for (const auto& step : driveBy({-2.5, 1.5}, {2.5, 1.5}, 0.0)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  for (const auto& step : driveBy({2.5, -1.5}, {-2.5, -1.5}, kPi)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  const BatchResult baseline =
      processBatch(scans, MapperOptions{}, BatchOptions{}, BatchMode::kPlainGrid);
  const BatchResult full = processBatch(scans, MapperOptions{}, BatchOptions{}, BatchMode::kFull);
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

TEST(BatchProcessor, RecordingTooLargeForOneWindowIsRejected) {
  SyntheticWorld world = roomWithPane();
  const std::vector<TimedScan> scans = {world.timedScan(Pose2D{{0.0, 0.0}, 0.0}, 0.0),
                                        world.timedScan(Pose2D{{420.0, 0.0}, 0.0}, 0.025)};
  for (BatchMode mode : {BatchMode::kPlainGrid, BatchMode::kFull}) {
    try {
      processBatch(scans, MapperOptions{}, BatchOptions{}, mode);
      ADD_FAILURE() << "a recording 420 m across was accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find("at most 400 m across"), std::string::npos)
          << error.what();
    }
  }
}

// A corridor 3 m wide, closed 15.5 m ahead of where the robot starts.
SyntheticWorld longCorridor() {
  SyntheticWorld world;
  world.addWall({-1.0, -1.5}, {15.5, -1.5});
  world.addWall({-1.0, 1.5}, {15.5, 1.5});
  world.addWall({15.5, -1.5}, {15.5, 1.5});
  world.addWall({-1.0, -1.5}, {-1.0, 1.5});
  return world;
}

TEST(BatchProcessor, RaysAddEvidenceOnlyWithinTheRadiusAsLive) {
  // The robot never comes within 5 m of the corridor's end, which lies inside the batch's window.
  // A person stands 7-8 m ahead of it at first (too far to add evidence), then leaves, and the
  // robot drives over the spot.
  SyntheticWorld world = longCorridor();
  MapperOptions options;
  options.active_region.active_region_radius = 5.0;
  const Eigen::Vector2d person(8.0, 0.0);
  std::vector<TimedScan> scans;
  size_t scans_with_person = 0;
  for (const auto& step : driveBy({0.0, 0.0}, {10.0, 0.0}, 0.0)) {
    world.people.clear();
    if (step.robot.position.x() < 1.0) {
      world.people.push_back({person, 0.25});
      ++scans_with_person;
    }
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  const int ahead = 540;  // the beam along the corridor
  const GridGeometry g(0.05, 180);
  for (BatchMode mode : {BatchMode::kBasicRfm, BatchMode::kFull, BatchMode::kPlainGrid}) {
    SCOPED_TRACE(static_cast<int>(mode));
    const BatchResult result = processBatch(scans, options, BatchOptions{}, mode);
    ASSERT_EQ(result.labels.size(), scans.size());
    // The end wall, 5.5 m or more from every view, got no evidence: unknown, as live.
    for (const CellIndex& end_wall : {g.cellOf({15.48, 0.0}), g.cellOf({15.48, 1.0})}) {
      EXPECT_TRUE(result.map.bounds().contains(end_wall));
      EXPECT_EQ(result.map.get(end_wall), CellClass::kUnknown);
    }
    // Beams ending there are not judged: kept.
    for (size_t i = scans_with_person; i < scans.size(); ++i)
      ASSERT_EQ(result.labels[i][ahead], RayLabel::kKept) << "scan " << i;
    // The person's spot was seen free from closer: the beams that ended on the person are judged.
    EXPECT_EQ(occupancyValue(result.map.get(g.cellOf(person))), 0);
    for (size_t i = 0; i < scans_with_person; ++i) {
      ASSERT_TRUE(std::isfinite(scans[i].scan.ranges[ahead]));
      ASSERT_NE(result.labels[i][ahead], RayLabel::kKept) << "scan " << i;
    }
  }
}

TEST(BatchProcessor, EveryNthScanOfEachSensorKeepsEachSensorsOrder) {
  std::vector<TimedScan> scans(10);
  for (size_t i = 0; i < scans.size(); ++i) {
    scans[i].sensor_id = static_cast<uint32_t>(i % 2);
    scans[i].stamp = static_cast<double>(i);  // the scan's index
  }
  std::vector<double> indices;
  for (const TimedScan* scan : everyNthScanOfEachSensor(scans, 3))
    indices.push_back(scan->stamp);
  // Sensor 0 has scans 0, 2, 4, 6, 8 (its 0th and 3rd: 0 and 6); sensor 1 has 1, 3, ... (1, 7).
  EXPECT_EQ(indices, (std::vector<double>{0, 1, 6, 7}));
  EXPECT_EQ(everyNthScanOfEachSensor(scans, 1).size(), scans.size());
}

// The batch classifies with batch_beta, not the live beta: with a batch_beta no cell can reach,
// nothing is widely visible, whatever beta says (and no cell is static for being solid).
TEST(BatchProcessor, BatchClassifiesWithBatchBeta) {
  const std::vector<TimedScan> scans = paneWithWallBehind(1);
  auto static_cells = [&](MapperOptions options, const BatchOptions& batch) {
    options.motion_removal.solid_max_missed_ratio = 0.0;
    const GlobalMap2D map = processBatch(scans, options, batch, BatchMode::kMotionRemoval).map;
    std::vector<CellClass> classes;
    map.extract(map.bounds(), classes);
    return std::count(classes.begin(), classes.end(), CellClass::kStatic);
  };
  BatchOptions unreachable_batch_beta;
  unreachable_batch_beta.batch_beta = 10000.0;
  EXPECT_EQ(static_cells(testing::scenarioOptions(), unreachable_batch_beta), 0);
  MapperOptions unreachable_beta = testing::scenarioOptions();
  unreachable_beta.occupancy.beta = 10000.0;
  EXPECT_GT(static_cells(unreachable_beta, BatchOptions{}), 50);  // the wall, the frames
}

// The batch's passes before the last take every Nth scan of each sensor, the last every scan:
// the progress it reports counts the scans each pass inserted, then the labelled ones.
TEST(BatchProcessor, SearchPassesInsertEveryNthScanAndTheLastEveryScan) {
  const std::vector<TimedScan> scans = paneWithWallBehind(2);
  const size_t n = scans.size();
  auto per_pass = [&](int stride) { return everyNthScanOfEachSensor(scans, stride).size(); };
  ASSERT_EQ(per_pass(8), (n / 2 + 7) / 8 + ((n + 1) / 2 + 7) / 8);

  BatchOptions batch;
  batch.first_pass_scan_stride = 8;
  batch.search_pass_scan_stride = 2;
  for (int iterations : {2, 5}) {
    SCOPED_TRACE(iterations);
    batch.max_reflection_iterations = iterations;
    size_t last_done = 0, last_total = 0;
    const BatchResult full = processBatch(scans, testing::scenarioOptions(), batch,
                                          BatchMode::kFull, [&](size_t done, size_t total) {
                                            last_done = done;
                                            last_total = total;
                                          });
    // Passes 0 (every 8th), 1 .. k-2 (every 2nd), k-1 (every scan), then the labelling. A
    // search pass whose glass settled hands over to the last pass at once.
    const int passes = full.timings.reflection_iterations;
    ASSERT_GE(passes, 3);
    EXPECT_LE(passes, iterations + 1);
    EXPECT_EQ(last_done, last_total);
    EXPECT_EQ(last_total, per_pass(8) + (passes - 2) * per_pass(2) + n + n);
    if (iterations == 5) {
      EXPECT_LT(passes, 6) << "the settled glass was searched again";
    }
    EXPECT_GT(countLabels(full.labels).reflection, 0u);
  }
}

// A row of `count` glass cells at y, from x.
detail::GlassCells glassRow(int x, int y, int count) {
  detail::GlassCells cells;
  for (int i = 0; i < count; ++i)
    cells.insert({x + i, y});
  return cells;
}

TEST(GlassPasses, UnderOnePercentChangedSinceThePassBeforeIsConverged) {
  detail::GlassPasses passes;
  EXPECT_EQ(passes.add(glassRow(0, 0, 200)), detail::GlassPassOutcome::kChanged);  // the first
  // Two cells of 200 more: 1 %.
  EXPECT_EQ(passes.add(glassRow(0, 0, 202)), detail::GlassPassOutcome::kConverged);
  // Three of 205 more, 1.5 %.
  EXPECT_EQ(passes.add(glassRow(0, 0, 205)), detail::GlassPassOutcome::kChanged);
}

TEST(GlassPasses, AStateSeenBeforeEndsAnAlternation) {
  detail::GlassPasses passes;
  const detail::GlassCells near_pane = glassRow(0, 0, 100), far_pane = glassRow(0, 30, 100);
  EXPECT_EQ(passes.add(near_pane), detail::GlassPassOutcome::kChanged);
  EXPECT_EQ(passes.add(far_pane), detail::GlassPassOutcome::kChanged);
  EXPECT_EQ(passes.add(near_pane), detail::GlassPassOutcome::kCycle);
}

// Two parallel panes: the paper reports Alg. 3 may not converge. It must end, keeping both
// (the stop rule itself: GlassPasses above).
TEST(BatchProcessor, TwoParallelPanesTerminateWithBothKept) {
  SyntheticWorld world;
  world.addFramedPane({2.0, -3.0}, {2.0, 3.0});
  world.addFramedPane({3.5, -3.0}, {3.5, 3.0});
  world.addWall({6.0, -6.0}, {6.0, 6.0});
  std::vector<TimedScan> scans;
  for (const auto& step : driveBy({0.0, -4.0}, {0.0, 4.0}, kPi / 2)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  for (const auto& step : driveBy({5.0, 4.0}, {5.0, -4.0}, -kPi / 2)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  BatchOptions batch;
  batch.max_reflection_iterations = 6;
  const BatchResult full = processBatch(scans, testing::scenarioOptions(), batch, BatchMode::kFull);
  EXPECT_LE(full.timings.reflection_iterations, 6);
  const GridGeometry g(0.05, 180);
  for (double x : {2.0, 3.5}) {
    int kept = 0, total = 0;
    for (double y = -2.8; y <= 2.8; y += 0.05, ++total) {
      kept += isObstacle(full.map.get(g.cellOf({x + 1e-3, y}))) ||
              isObstacle(full.map.get(g.cellOf({x - 1e-3, y})));
    }
    EXPECT_GT(kept, 0.9 * total) << "pane at x = " << x;
  }
}

}  // namespace
}  // namespace rfm
