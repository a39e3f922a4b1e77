#include "reflectance_field_map/core/batch_processor.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/ray_insertion.h"

#include "scenario.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

namespace rfm {
namespace {

using testing::driveBy;
using testing::roomWithPane;
using testing::runScenario;
using testing::SyntheticWorld;

TEST(Mapper, MalformedScansAreRejectedAndChangeNothing) {
  Mapper mapper(MapperOptions{});
  TimedScan scan = roomWithPane().timedScan({{0.0, 0.0}, 0.0});
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
  TimedScan scan = roomWithPane().timedScan({{0.0, 0.0}, 0.0});
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
  SyntheticWorld world = roomWithPane();
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

// removeMotion() in its two steps leaves the mapper as removeMotion() does: the same labels for
// every scan and the same state saved.
TEST(Mapper, APassInTwoStepsGivesWhatRemoveMotionGives) {
  const SyntheticWorld world = testing::paneWithWallBehindWorld();
  const std::vector<testing::ScenarioStep> steps = testing::driveAlongThePane();
  Mapper whole(testing::scenarioOptions()), split(testing::scenarioOptions());
  int passes_with_new_glass = 0;
  for (size_t i = 0; i < steps.size(); ++i) {
    const TimedScan scan = world.timedScan(steps[i].robot, 0.025 * i);
    const std::vector<RayLabel> labels = whole.labelAddedScan(scan, whole.addScan(scan));
    ASSERT_EQ(split.labelAddedScan(scan, split.addScan(scan)), labels) << "scan " << i;
    if ((i + 1) % 20 != 0) continue;
    const bool new_glass = whole.removeMotion().new_glass;
    passes_with_new_glass += new_glass;
    split.classifyActiveRegion();
    EXPECT_EQ(split.revertPending(), new_glass) << "scan " << i;
    split.revertBehindNewGlass();
    EXPECT_FALSE(split.revertPending());
  }
  EXPECT_GT(passes_with_new_glass, 0);
  auto saved = [](const Mapper& mapper) {
    std::ostringstream out;
    mapper.save(out);
    return out.str();
  };
  EXPECT_TRUE(saved(split) == saved(whole));
}

// A live caller spreads a pass's revert over the scans after it (the node's order: the scan's
// labels, a part of the revert, a pass when due): each revert is done within a few scans. One
// still pending when the active region moves is finished before the move, inside the scan that
// moves it. The parts grow as the robot nears a move: at a steady speed a revert that has a few
// scans before the move is done in parts before it.
TEST(Mapper, ARevertInPartsEndsBeforeTheNextPassAndBeforeTheRegionMoves) {
  const SyntheticWorld world = testing::paneWithWallBehindWorld();
  const std::vector<testing::ScenarioStep> steps = testing::driveAlongThePane();  // along +y
  std::vector<TimedScan> scans;
  std::vector<bool> moves;  // whether the scan moves the active region
  Mapper probe(testing::scenarioOptions());
  for (size_t i = 0; i < steps.size(); ++i) {
    scans.push_back(world.timedScan(steps[i].robot, 0.025 * i));
    moves.push_back(probe.addScan(scans.back()).region_moved);
  }
  Mapper parts(testing::scenarioOptions()), left(testing::scenarioOptions());
  int reverts = 0, spread_near_a_move = 0, finished_by_a_move = 0;
  size_t scans_left = 0;    // before the region moves, at the last pass
  size_t revert_parts = 0;  // of the revert under way
  for (size_t i = 0; i < scans.size(); ++i) {
    const bool pending = parts.revertPending();
    EXPECT_EQ(parts.addScan(scans[i]).region_moved, moves[i]) << "scan " << i;
    if (moves[i] && scans_left >= 4) {
      EXPECT_FALSE(pending) << "scan " << i << ": a revert left to the move";
    }
    const size_t before = parts.stats().reverted_scans;
    parts.revertPartBehindNewGlass();
    revert_parts += parts.stats().reverted_scans > before;

    const bool was_pending = left.revertPending();
    const ScanUpdate update = left.addScan(scans[i]);  // no parts: only a move ends its revert
    if (update.region_moved) {
      EXPECT_FALSE(left.revertPending()) << "scan " << i;
    }
    finished_by_a_move += was_pending && update.region_moved;
    if ((i + 1) % 20 != 0 && i + 1 != scans.size()) continue;
    EXPECT_FALSE(parts.revertPending()) << "scan " << i;
    // 0.15 m from the move (the robot makes 2.5 cm a scan), a revert still goes in parts.
    spread_near_a_move += scans_left <= 6 && revert_parts > 1;
    reverts += parts.classifyActiveRegion().new_glass;
    left.classifyActiveRegion();
    revert_parts = 0;
    scans_left = std::find(moves.begin() + i + 1, moves.end(), true) - moves.begin() - i - 1;
  }
  EXPECT_GT(reverts, 0);
  EXPECT_GT(spread_near_a_move, 0);
  EXPECT_GT(finished_by_a_move, 0);
  // Each revert took back every scan it marked.
  parts.revertBehindNewGlass();
  left.revertBehindNewGlass();
  EXPECT_GT(parts.stats().reverted_scans, 0u);
  EXPECT_EQ(left.stats().reverted_scans, parts.stats().reverted_scans);
}

TEST(Mapper, ResetForgetsEverything) {
  SyntheticWorld world = roomWithPane();
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

// A batch holds its recording in a window that stays where it is held, whatever the robot does.
TEST(Mapper, HeldActiveRegionStaysWhereItIsHeld) {
  SyntheticWorld world;
  world.addWall({0.0, 2.0}, {40.0, 2.0});
  world.addWall({0.0, -2.0}, {40.0, -2.0});
  Mapper mapper(testing::scenarioOptions());
  mapper.holdActiveRegionAt({3.0, 0.0});
  runScenario(mapper, world, driveBy({1.0, 0.0}, {39.0, 0.0}, 0.0));
  const GridGeometry& g = mapper.field().geometry();
  // Unheld, the start of the corridor leaves the region (GlobalMapKeepsWhatTheActiveRegionLeft-
  // Behind) and the robot's end is in it.
  EXPECT_TRUE(mapper.field().inActiveRegion(g.cellOf({3.0, 0.0})));
  EXPECT_FALSE(mapper.field().inActiveRegion(g.cellOf({39.0, 0.0})));
  EXPECT_FALSE(mapper.field().wouldRecenter({3.0, 0.0}));
  EXPECT_EQ(mapper.stats().archived_bytes, 0u);  // no tile ever left the region
  EXPECT_EQ(mapper.cellClass(g.cellOf({3.0, 0.0})), CellClass::kFree);
}

// A scan that makes the anchor rules' persistence tick due leaves it for runDueTick (a live
// caller runs it once the scan's labels are out): addScan itself never ticks then.
TEST(Mapper, ADueTickWaitsForRunDueTick) {
  SyntheticWorld world;
  world.addWall({0.0, 2.0}, {40.0, 2.0});
  world.addWall({0.0, -2.0}, {40.0, -2.0});
  Mapper mapper(testing::scenarioOptions());
  mapper.holdActiveRegionAt({3.5, 0.0});  // no tile leaves the window and its histories
  auto confirmed_ticks = [&mapper] {
    long sum = 0;
    const ReflectanceField& field = mapper.field();
    field.window().forEachCell(field.activeBox(), [&](int, int, int slot) {
      sum += mapper.anchorHistory().confirmedTicksAt(slot);
    });
    return sum;
  };
  int i = 0, ticks_run = 0;
  long before = 0;
  for (const auto& step : driveBy({1.0, 0.0}, {6.0, 0.0}, 0.0)) {
    mapper.addScan(world.timedScan(step.robot, 0.025 * i++));
    ASSERT_EQ(confirmed_ticks(), before) << "addScan ticked, scan " << i;
    mapper.runDueTick();
    const long after = confirmed_ticks();
    ticks_run += after != before;
    before = after;
  }
  EXPECT_GT(ticks_run, 3);
}

// A corridor whose south wall holds a framed pane, with a wall seen through it.
SyntheticWorld corridorWithPane() {
  SyntheticWorld world;
  world.addWall({0.0, 2.0}, {40.0, 2.0});
  world.addWall({0.0, -2.0}, {6.0, -2.0});
  world.addFramedPane({6.0, -2.0}, {10.0, -2.0});
  world.addWall({10.0, -2.0}, {40.0, -2.0});
  world.addWall({8.0, -6.0}, {12.0, -6.0});  // seen through the glass
  return world;
}

// Same field, persistence and classes as addScan one by one, while the window moves, ticks
// fall inside groups of scans and (with reflection removal) known glass cuts rays. With
// `restart`, halfway both restart their evidence and take the scans again (batch
// re-processing: the glass check then reads frozen reflectivity, grouped by addScans). With the
// sensor `sensor_ahead` m ahead of the robot, rays reach beyond the robot-centred window and
// must be clipped to it before either path inserts them.
void expectAddScansMatchesAddScan(bool reflection_removal, bool restart = false,
                                  double sensor_ahead = 0.0) {
  SyntheticWorld world = corridorWithPane();
  MapperOptions options = testing::scenarioOptions();
  options.reflection_removal.reflection_removal_enabled = reflection_removal;
  Mapper one_by_one(options), grouped(options);
  std::vector<TimedScan> scans;
  int i = 0;
  // Facing back while driving on, so rays reach the tiles the window leaves behind.
  for (const auto& step : driveBy({1.0, 0.0}, {16.0, 0.0}, kPi - 0.3)) {
    TimedScan scan = world.timedScan(step.robot, 0.025 * i++);
    if (sensor_ahead != 0.0) {
      const double yaw = step.robot.yaw;
      scan.sensor_pose.position += sensor_ahead * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
      scan.scan = world.scan(scan.sensor_pose);
    }
    scans.push_back(std::move(scan));
  }
  size_t rays_beyond_window = 0;
  std::vector<Ray> rays;
  constexpr size_t kGroup = 33;  // not a multiple of the 20 scans between ticks
  for (int pass = 0; pass < (restart ? 2 : 1); ++pass) {
    if (pass > 0) {
      one_by_one.restartEvidence();
      grouped.restartEvidence();
    }
    for (size_t first = 0; first < scans.size(); first += kGroup) {
      const size_t last = std::min(scans.size(), first + kGroup);
      for (size_t k = first; k < last; ++k) {
        one_by_one.addScan(scans[k]);
        // The window the scan went into, and its rays as far as they add evidence.
        const CellBox box = one_by_one.field().activeBox();
        scanToRays(scans[k].scan, scans[k].sensor_pose, options.insertion, rays);
        for (Ray& ray : rays) {
          clipRayToLength(options.active_region.active_region_radius, ray);
          rays_beyond_window += !box.contains(one_by_one.field().geometry().cellOf(ray.end));
        }
      }
      grouped.addScans(scans.begin() + first, scans.begin() + last);
      // Re-processing (Alg. 3) runs motion removal once, at the end of its pass.
      if (pass == 0 || last == scans.size()) {
        one_by_one.removeMotion();
        grouped.removeMotion();
      }
    }
  }
  const ReflectanceField& a = one_by_one.field();
  const ReflectanceField& b = grouped.field();
  const AnchorHistory& a_history = one_by_one.anchorHistory();
  const AnchorHistory& b_history = grouped.anchorHistory();
  ASSERT_EQ(a.activeBox().min, b.activeBox().min);
  EXPECT_TRUE(a.wouldRecenter({1.0, 0.0}));  // the window moved on from the start
  size_t reflective = 0, confirmed = 0;
  a.window().forEachCell(a.activeBox(), [&](int, int, int slot) {
    ASSERT_EQ(a.reflectiveBinsAt(slot), b.reflectiveBinsAt(slot));
    ASSERT_EQ(a.missedBinsAt(slot), b.missedBinsAt(slot));
    ASSERT_EQ(a_history.confirmedTicksAt(slot), b_history.confirmedTicksAt(slot));
    reflective += a.reflectiveBinsAt(slot);
    confirmed += a_history.confirmedTicksAt(slot) > 0;
  });
  for (int y = a.activeBox().min.y(); y < a.activeBox().max.y(); ++y) {
    for (int x = a.activeBox().min.x(); x < a.activeBox().max.x(); ++x) {
      for (int bin = 0; bin < a.geometry().thetaBins(); ++bin)
        ASSERT_EQ(a.value({x, y}, bin), b.value({x, y}, bin)) << x << " " << y << " " << bin;
    }
  }
  EXPECT_GT(reflective, 1000u);
  EXPECT_GT(confirmed, 100u);
  if (sensor_ahead > 0.0) {
    EXPECT_GT(rays_beyond_window, 1000u);
  } else {
    EXPECT_EQ(rays_beyond_window, 0u);
  }
  EXPECT_EQ(one_by_one.stats().scans_processed, grouped.stats().scans_processed);
  EXPECT_EQ(one_by_one.stats().reflection_rays, grouped.stats().reflection_rays);
  if (reflection_removal) {
    EXPECT_GT(grouped.stats().reflection_rays, 0u);
  }
  std::vector<CellClass> classes_a, classes_b;
  one_by_one.map().extract(one_by_one.map().bounds(), classes_a);
  grouped.map().extract(one_by_one.map().bounds(), classes_b);
  EXPECT_EQ(classes_a, classes_b);
  // Everything else too, the evidence of the tiles that left the window included.
  EXPECT_GT(a.archivedTiles(), 0u);
  std::stringstream state_a, state_b;
  one_by_one.save(state_a);
  grouped.save(state_b);
  EXPECT_TRUE(state_a.str() == state_b.str());
}

TEST(Mapper, AddScansGivesWhatAddScanGivesOneByOne) {
  expectAddScansMatchesAddScan(false);
}

TEST(Mapper, AddScansGivesWhatAddScanGivesWithReflectionRemoval) {
  expectAddScansMatchesAddScan(true);
}

TEST(Mapper, AddScansGivesWhatAddScanGivesAfterRestartingTheEvidence) {
  expectAddScansMatchesAddScan(true, /*restart=*/true);
}

TEST(Mapper, AddScansGivesWhatAddScanGivesWithRaysBeyondTheWindow) {
  // The window holds the active region around the robot, not around a sensor mounted ahead.
  // Without reflection removal every group goes into the field together (insertScans, which
  // takes the mapper's rays as already clipped to the window).
  expectAddScansMatchesAddScan(false, /*restart=*/false, /*sensor_ahead=*/1.2);
}

// Scans back to back (a batch, a fast replay) share their work with the helper threads; scans
// that come after a pause, as live scans do, are done by the caller alone, and the field, the
// classes and the labels come out the same.
TEST(Mapper, ScansAfterAPauseGoInWithoutTheHelpersAndGiveTheSameMap) {
  SyntheticWorld world = corridorWithPane();
  std::vector<TimedScan> scans;
  int i = 0;
  for (const auto& step : driveBy({1.0, 0.0}, {9.0, 0.0}, 0.0))
    scans.push_back(world.timedScan(step.robot, 0.025 * i++));
  MapperOptions options = testing::scenarioOptions();
  options.insertion.insertion_threads = 2;
  // Returns each scan's update; with `pause`, waits longer than the helpers spin before each.
  auto map = [&](Mapper& mapper, bool pause) {
    std::vector<ScanUpdate> updates;
    for (size_t k = 0; k < scans.size(); ++k) {
      if (pause) std::this_thread::sleep_for(4 * ParallelRunner::kSpinTime);
      updates.push_back(mapper.addScan(scans[k]));
      if (k % 20 == 19) mapper.removeMotion();
    }
    return updates;
  };
  Mapper back_to_back(options), paused(options);
  const std::vector<ScanUpdate> a = map(back_to_back, false);
  const std::vector<ScanUpdate> b = map(paused, true);
  size_t shared = 0;
  for (size_t k = 0; k < scans.size(); ++k) {
    ASSERT_FALSE(b[k].shared) << "scan " << k;
    ASSERT_EQ(a[k].labels, b[k].labels) << "scan " << k;
    shared += a[k].shared;
  }
  // The first scan follows no other; a few more may follow a caller the system descheduled.
  EXPECT_GT(shared, scans.size() / 2);
  EXPECT_GT(back_to_back.stats().reflection_rays, 0u);
  std::stringstream state_a, state_b;
  back_to_back.save(state_a);
  paused.save(state_b);
  EXPECT_TRUE(state_a.str() == state_b.str());
}

// Live labels of a scan just added (labelAddedScan), beam by beam, keyed by what the beam hit.
struct LiveLabels {
  std::vector<RayLabel> labels;
  TimedScan scan;
};

LiveLabels addAndLabel(Mapper& mapper, const SyntheticWorld& world, const Pose2D& robot,
                       double stamp) {
  LiveLabels out;
  out.scan = world.timedScan(robot, stamp);
  out.labels = mapper.labelAddedScan(out.scan, mapper.addScan(out.scan));
  return out;
}

// A room the robot, standing at the origin, has watched empty for `scans_watched` scans (a second
// by default), motion removal run: its floor is free, seen free from where the robot stands.
struct WatchedEmptyRoom {
  explicit WatchedEmptyRoom(int scans_watched = 40) : mapper(testing::scenarioOptions()) {
    world.addWall({5.0, -3.0}, {5.0, 3.0});
    world.addWall({-1.0, 3.0}, {5.0, 3.0});
    world.addWall({-1.0, -3.0}, {5.0, -3.0});
    for (int i = 0; i < scans_watched; ++i)
      look();
    mapper.removeMotion();
  }
  LiveLabels look() { return addAndLabel(mapper, world, robot, stamp += 0.025); }

  SyntheticWorld world;
  Mapper mapper;
  const Pose2D robot{Eigen::Vector2d(0.0, 0.0), 0.0};
  double stamp = 0.0;
};

// A person steps into floor the robot has watched empty, in the direction it now sees them
// from: the live labels remove them at once, before motion removal has seen them move.
TEST(Mapper, LiveLabelsRemoveSomeoneSteppingIntoFloorSeenEmpty) {
  WatchedEmptyRoom room;
  room.world.people = {{{2.5, 0.0}, 0.25}};
  const LiveLabels seen = room.look();
  int person = 0, person_removed = 0, wall = 0, wall_kept = 0;
  for (size_t i = 0; i < seen.labels.size(); ++i) {
    const double range = seen.scan.scan.ranges[i];
    if (!std::isfinite(range)) continue;
    if (range < 2.9) {  // the person; the walls are 3 m away or more
      ++person;
      person_removed += seen.labels[i] == RayLabel::kMotion;
    } else {
      ++wall;
      wall_kept += seen.labels[i] == RayLabel::kKept;
    }
  }
  ASSERT_GT(person, 10);
  // The silhouette's two edge beams stay: the beam beside each went on through its end cell.
  EXPECT_GE(person_removed, person - 2);
  EXPECT_EQ(wall_kept, wall);
}

// The beams of a scan nearer than `range` (m), and how many of them the live labels removed.
struct NearBeams {
  int beams = 0, removed = 0;
};
NearBeams nearBeams(const LiveLabels& seen, double range) {
  NearBeams near;
  for (size_t i = 0; i < seen.labels.size(); ++i) {
    if (!(seen.scan.scan.ranges[i] < range)) continue;
    ++near.beams;
    near.removed += seen.labels[i] == RayLabel::kMotion;
  }
  return near;
}

// Someone who stepped into floor seen empty stays in their cells for several scans, whose hits
// fill the bins that said the floor was free: the arrival judged at their first returns holds
// for the returns that follow there, until motion removal judges them.
TEST(Mapper, LiveLabelsKeepRemovingSomeoneWhoStaysWhereTheyArrived) {
  WatchedEmptyRoom room;
  room.world.people = {{{2.5, 0.0}, 0.25}};
  for (int scan = 0; scan < 10; ++scan) {
    const NearBeams person = nearBeams(room.look(), 2.9);  // the walls are 3 m away or more
    ASSERT_GT(person.beams, 10);
    EXPECT_GE(person.removed, person.beams - 2) << "scan " << scan;
  }
}

// Motion removal judges what arrived, and the marks go: a return where someone stepped in before
// the pass is judged afresh. Here a pole thinner than the beams' spacing, which the beams beside
// its return go past, stays kept (LiveLabelsKeepAReturnTheBeamsBesideItGoPast).
TEST(Mapper, LiveLabelsJudgeAfreshOnceMotionRemovalRan) {
  WatchedEmptyRoom room;
  room.world.people = {{{2.5, 0.0}, 0.25}};
  ASSERT_GT(nearBeams(room.look(), 2.9).removed, 10);  // their front, at 2.25 m, marked
  room.world.people.clear();
  room.mapper.removeMotion();
  room.world.people = {{{2.253, 0.0}, 0.003}};  // a 6 mm pole in that front's cell
  const NearBeams pole = nearBeams(room.look(), 2.9);
  ASSERT_GE(pole.beams, 1);
  EXPECT_EQ(pole.removed, 0);
}

// Floor seen free in only a few scans, as the cells of a pane are between the returns of its
// moving return cone, does not carry an arrival on: each scan's returns are judged afresh, and
// once the cell's bin holds their hits they stay kept until motion removal judges them.
TEST(Mapper, LiveLabelsJudgeAfreshWhereTheFloorWasSeenFreeOnlyBriefly) {
  WatchedEmptyRoom room(2);
  const GridGeometry& g = room.mapper.field().geometry();
  ASSERT_EQ(room.mapper.cellClass(g.cellOf({2.3, 0.0})), CellClass::kFree);
  room.world.people = {{{2.5, 0.0}, 0.25}};
  const NearBeams first = nearBeams(room.look(), 2.9);
  room.look();
  const NearBeams third = nearBeams(room.look(), 2.9);
  ASSERT_GT(first.beams, 10);
  EXPECT_GE(first.removed, first.beams - 2);  // an arrival: the bins said free
  EXPECT_EQ(third.removed, 0);                // the bins hold two hits each
}

// A pane the robot has only looked through obliquely (at the wall behind it) is free in the
// classes; seen for the first time near its normal it returns from directions no ray had crossed
// it in: kept, not an arrival.
TEST(Mapper, LiveLabelsKeepAPaneFirstSeenNearItsNormal) {
  SyntheticWorld world = corridorWithPane();
  Mapper mapper(testing::scenarioOptions());
  double stamp = 0.0;
  for (const auto& step : driveBy({6.0, 0.0}, {7.5, 0.0}, 0.0))
    addAndLabel(mapper, world, step.robot, stamp += 0.025);
  mapper.removeMotion();
  const GridGeometry& g = mapper.field().geometry();
  ASSERT_EQ(mapper.cellClass(g.cellOf({8.0, -2.0})), CellClass::kFree);

  const LiveLabels seen =
      addAndLabel(mapper, world, Pose2D{Eigen::Vector2d(8.0, 0.0), 0.0}, stamp += 0.025);
  int pane = 0, pane_kept = 0;
  for (size_t i = 0; i < seen.labels.size(); ++i) {
    const double range = seen.scan.scan.ranges[i];
    if (std::abs(range - 2.0) > 0.1) continue;  // the pane, straight below the robot
    ++pane;
    pane_kept += seen.labels[i] == RayLabel::kKept;
  }
  ASSERT_GT(pane, 3);
  EXPECT_EQ(pane_kept, pane);
}

// Beside a return from something thinner than the beams' spacing (the edge of a pane's return
// cone, a pole's rim) the scan's next beams go on through the same cell: the cell lets beams
// through, it is no arrival, and the return stays kept.
TEST(Mapper, LiveLabelsKeepAReturnTheBeamsBesideItGoPast) {
  WatchedEmptyRoom room;
  room.world.people = {{{2.5, 0.0}, 0.003}};  // a 6 mm pole: one beam of 0.25 deg (11 mm at 2.5 m)
  const LiveLabels seen = room.look();
  int pole = 0, pole_kept = 0;
  for (size_t i = 0; i < seen.labels.size(); ++i) {
    if (seen.scan.scan.ranges[i] >= 2.9) continue;
    ++pole;
    pole_kept += seen.labels[i] == RayLabel::kKept;
  }
  ASSERT_GE(pole, 1);
  EXPECT_EQ(pole_kept, pole);
}

}  // namespace
}  // namespace rfm
