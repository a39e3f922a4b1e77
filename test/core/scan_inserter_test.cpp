#include "reflectance_field_map/core/scan_inserter.h"

#include "reflectance_field_map/core/plain_occupancy_grid.h"

#include "synthetic_world.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace rfm {
namespace {

using testing::SyntheticWorld;

struct Fixture {
  Fixture() : field(testing::centredField(6.0)) {}
  ReflectanceField field;
  ScanInserter inserter;
};

Ray makeRay(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool hit, uint32_t beam = 0) {
  Ray ray;
  ray.origin = from;
  ray.end = to;
  ray.angle = std::atan2(to.y() - from.y(), to.x() - from.x());
  ray.hit = hit;
  ray.beam = beam;
  return ray;
}

// Rays longer than the evidence range lose their hit and end at the range, whatever the
// direction; rays up to it, to the last bit, keep theirs (the cut compares squares first).
TEST(ClipRayToLength, CutsOnlyRaysLongerThanTheRange) {
  constexpr double kRange = 10.0;
  for (const double angle : {0.0, 0.3, 1.0, 2.5, -2.0}) {
    const Eigen::Vector2d origin(1.25, -3.5), direction(std::cos(angle), std::sin(angle));
    for (const double length :
         {0.5, std::nextafter(kRange, 0.0), kRange, std::nextafter(kRange, 20.0), 10.001, 25.0}) {
      Ray ray;
      ray.origin = origin;
      ray.end = origin + length * direction;
      ray.hit = true;
      const Ray before = ray;
      clipRayToLength(kRange, ray);
      const double measured = (before.end - before.origin).norm();  // as the cut measures it
      if (measured > kRange) {
        EXPECT_FALSE(ray.hit) << "angle " << angle << " length " << length;
        EXPECT_NEAR((ray.end - ray.origin).norm(), kRange, 1e-9);
      } else {
        EXPECT_TRUE(ray.hit) << "angle " << angle << " length " << length;
        EXPECT_EQ(ray.end, before.end);
      }
    }
  }
}

// Rays inside the box are left as they are; a ray reaching the border's hair-wide margin, or
// beyond, is cut inside it and loses its hit, and one from outside starts at the border.
TEST(ClipRayToBox, KeepsRaysInsideAndCutsThemInsideTheBorder) {
  constexpr double kResolution = 0.05;
  const CellBox box{{0, 0}, {20, 20}};  // 1 m
  const GridGeometry geometry(kResolution, 180);
  auto clipped = [&](const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool& inside) {
    Ray ray;
    ray.origin = from;
    ray.end = to;
    ray.hit = true;
    inside = clipRayToBox(box, kResolution, ray);
    return ray;
  };
  bool inside = false;
  Ray ray = clipped({0.5, 0.5}, {0.9, 0.7}, inside);
  EXPECT_TRUE(inside);
  EXPECT_TRUE(ray.hit);
  EXPECT_EQ(ray.end, Eigen::Vector2d(0.9, 0.7));
  // Inside the box, but within its margin (5e-8 m) of the border: its cell would be the last.
  for (const Eigen::Vector2d& end : {Eigen::Vector2d(1.0 - 1e-8, 0.5), Eigen::Vector2d(1.5, 0.5)}) {
    ray = clipped({0.5, 0.5}, end, inside);
    EXPECT_TRUE(inside);
    EXPECT_FALSE(ray.hit) << end.x();
    EXPECT_LT(ray.end.x(), 1.0 - 1e-8) << end.x();
    EXPECT_TRUE(box.contains(geometry.cellOf(ray.end))) << end.x();
  }
  ray = clipped({-0.5, 0.5}, {0.5, 0.5}, inside);
  EXPECT_TRUE(inside);
  EXPECT_TRUE(ray.hit);
  EXPECT_NEAR(ray.origin.x(), 0.0, 1e-6);
  clipped({1.5, 1.5}, {2.0, 2.0}, inside);
  EXPECT_FALSE(inside);
}

TEST(ScanInserter, EachRayUpdatesOnlyItsThetaSlice) {
  Fixture f;
  f.inserter.insert({makeRay({0.01, 0.01}, {1.01, 0.01}, true)}, f.field);
  const int bin = f.field.geometry().binOf(0.0);
  for (int x = 0; x < 20; ++x) {
    EXPECT_LT(f.field.value({x, 0}, bin), 0) << x;  // misses along the way
    for (int other : {bin + 1, 179, 90})
      EXPECT_EQ(f.field.value({x, 0}, other), 0);
  }
  EXPECT_GT(f.field.value({20, 0}, bin), 0);  // the hit
  EXPECT_EQ(f.field.value({21, 0}, bin), 0);  // nothing beyond
}

TEST(ScanInserter, OneUpdatePerCellAndBinPerScanAndHitsWin) {
  Fixture f;
  const LogOddsModel& model = f.field.logOdds();
  // Three rays in the same bin cross cell (10, 0); one of them ends there.
  std::vector<Ray> rays = {makeRay({0.01, 0.01}, {1.01, 0.01}, true),
                           makeRay({0.01, 0.02}, {0.52, 0.02}, true),
                           makeRay({0.01, 0.03}, {1.51, 0.03}, false)};
  const size_t updates = f.inserter.insert(rays, f.field);
  const int bin = f.field.geometry().binOf(0.0);
  EXPECT_EQ(f.field.value({10, 0}, bin), model.hit(0));   // hit won, applied once
  EXPECT_EQ(f.field.value({5, 0}, bin), model.miss(0));   // three misses count once
  EXPECT_EQ(f.field.value({20, 0}, bin), model.hit(0));   // hit of ray 0, not missed by ray 2
  EXPECT_EQ(f.field.value({30, 0}, bin), model.miss(0));  // end of the cleared stretch
  EXPECT_EQ(updates, 31u);                                // cells 0..30 of one slice, once each
  // The next scan updates them again.
  f.inserter.insert(rays, f.field);
  EXPECT_EQ(f.field.value({5, 0}, bin), model.miss(model.miss(0)));
}

// Alg. 1 ray by ray: per theta bin, a hit on each hit ray's end cell and a miss on every other
// cell its rays cross, each (cell, bin) once.
std::vector<BinUpdate> referenceUpdates(const std::vector<Ray>& rays,
                                        const ReflectanceField& field) {
  const RollingWindow& window = field.window();
  const double inverse_resolution = field.geometry().inverseResolution();
  std::set<std::pair<int, int>> hits, misses;  // (slot, bin)
  for (const Ray& ray : rays) {
    const int bin = field.geometry().binOf(ray.angle);
    if (ray.hit) hits.insert({window.storageIndex(field.geometry().cellOf(ray.end)), bin});
    walkWindowCells(ray.origin, ray.end, inverse_resolution, window, true, [&](int slot, int, int) {
      misses.insert({slot, bin});
      return true;
    });
  }
  std::vector<BinUpdate> updates;
  for (const auto& [slot, bin] : misses) {
    const bool hit = hits.count({slot, bin}) > 0;
    updates.push_back({slot, static_cast<int16_t>(bin), hit});
  }
  return updates;  // sorted by (slot, bin), as the set was
}

TEST(ScanInserter, UpdatesMatchAlgorithmOneRayByRayOnRandomScans) {
  // Scans as a lidar makes them (one origin, beams in order, any lengths, some without a
  // return), from coarse to far finer than 8 beams a bin, where one bin's beams form several
  // fans whose cells overlap.
  ReflectanceField field = testing::centredField(8.0);
  ScanInserter inserter;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  constexpr double kIncrements[] = {0.0044, 0.0005, 0.02};  // rad: 0.25, 0.03 and 1.1 deg
  std::vector<BinUpdate> swept;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector2d origin(4.0 * unit(rng) - 2.0, 4.0 * unit(rng) - 2.0);
    const double increment = kIncrements[trial % 3];
    const int beams = 1 + static_cast<int>(unit(rng) * (trial % 3 == 1 ? 2000 : 1081));
    const double first_angle = unit(rng) * 2 * kPi;
    std::vector<Ray> rays;
    for (int k = 0; k < beams; ++k) {
      const double angle = first_angle + k * increment;
      const double range = unit(rng) < 0.3 ? 5.5 : 0.2 + 5.0 * unit(rng);
      Ray ray = makeRay(origin, origin + range * Eigen::Vector2d(std::cos(angle), std::sin(angle)),
                        unit(rng) < 0.8, static_cast<uint32_t>(k));
      ray.angle = wrapTwoPi(angle);
      rays.push_back(ray);
    }
    inserter.collectUpdates(rays, field, swept);
    // Grouped by bin in ascending order, a slot once per bin (what a revert pairs by).
    for (size_t i = 1; i < swept.size(); ++i) {
      ASSERT_LE(swept[i - 1].bin, swept[i].bin) << "trial " << trial << ", update " << i;
    }
    std::sort(swept.begin(), swept.end());
    ASSERT_EQ(std::adjacent_find(swept.begin(), swept.end(),
                                 [](const BinUpdate& a, const BinUpdate& b) {
                                   return a.slot == b.slot && a.bin == b.bin;
                                 }),
              swept.end())
        << "trial " << trial;
    ASSERT_EQ(swept, referenceUpdates(rays, field)) << "trial " << trial;
  }
}

TEST(ScanInserter, StampsFromBeforeTheirWrapAroundAreNotTakenForNewOnes) {
  // Each group (a scan's rays of one theta bin) takes the next 16-bit stamp. A ray's cells left
  // untouched for exactly 65535 groups meet the same stamp value again after the wrap: unless
  // the stamps were cleared, its end cell looks done already and gets no update.
  ReflectanceField field = testing::centredField(6.0);
  ScanInserter inserter;
  const std::vector<Ray> probe = {makeRay({0.01, 0.02}, {1.01, 0.02}, true)};
  auto far_rays = [](int count, double spacing) {  // one ray per bin for spacing 2 deg
    std::vector<Ray> rays;
    for (int k = 0; k < count; ++k) {
      const double angle = (k + 0.5) * spacing;
      rays.push_back(makeRay({2.5, 2.5}, {2.5 + 0.5 * std::cos(angle), 2.5 + 0.5 * std::sin(angle)},
                             true, static_cast<uint32_t>(k)));
    }
    return rays;
  };
  std::vector<BinUpdate> first, updates;
  inserter.collectUpdates(probe, field, first);  // stamp 1
  const std::vector<Ray> all_bins = far_rays(180, kTwoPi / 180);
  for (int scan = 0; scan < 364; ++scan)  // 65520 groups
    inserter.collectUpdates(all_bins, field, updates);
  inserter.collectUpdates(far_rays(14, kTwoPi / 180), field, updates);  // 65534
  inserter.collectUpdates(probe, field, updates);                       // stamp 1 again
  EXPECT_EQ(updates, first);
}

TEST(ScanInserter, RaysLeavingTheWindowKeepMissesAndLoseTheirHit) {
  Fixture f;
  const CellBox box = f.field.activeBox();
  const double edge = box.max.x() * 0.05;
  f.inserter.insert({makeRay({0.01, 0.01}, {edge + 3.0, 0.01}, true)}, f.field);
  const int bin = f.field.geometry().binOf(0.0);
  EXPECT_LT(f.field.value({box.max.x() - 1, 0}, bin), 0);
  for (int x = 0; x < box.max.x(); ++x)
    ASSERT_LE(f.field.value({x, 0}, bin), 0);
}

TEST(ScanInserter, SeveralSensorsWithTheirOwnPoses) {
  Fixture f;
  SyntheticWorld world;
  world.addWall({2.0, -3.0}, {2.0, 3.0});
  std::vector<Ray> rays, front, rear;
  scanToRays(world.scan({{0.3, 0.0}, 0.0}), {{0.3, 0.0}, 0.0}, InsertionOptions(), front);
  scanToRays(world.scan({{-0.3, 0.0}, kPi}), {{-0.3, 0.0}, kPi}, InsertionOptions(), rear);
  rays = front;
  rays.insert(rays.end(), rear.begin(), rear.end());
  f.inserter.insert(rays, f.field);
  // The wall is seen by the front sensor from +x travelling rays.
  const CellIndex wall = f.field.geometry().cellOf({2.0 + 1e-3, 0.0});
  EXPECT_TRUE(f.field.isReflective(wall, f.field.geometry().binOf(0.0)));
  // The rear sensor cleared space behind the robot along -x.
  const CellIndex behind = f.field.geometry().cellOf({-2.0, 0.0});
  const int backwards = f.field.geometry().binOf(kPi);  // the beam may round to either side
  EXPECT_LT(std::min(f.field.value(behind, backwards), f.field.value(behind, backwards - 1)), 0);
}

// Two threads, each writing its own theta bins, leave the field exactly as one thread does:
// bins, reflective masks and the per-cell counts.
TEST(ScanInserter, TwoThreadsGiveTheFieldOfOne) {
  SyntheticWorld world;
  world.addFramedPane({3.0, -4.0}, {3.0, 4.0});
  world.addWall({6.0, -8.0}, {6.0, 8.0});
  world.addWall({-5.0, -8.0}, {-5.0, 8.0});
  ReflectanceField single = testing::centredField(12.0);
  ReflectanceField parallel = testing::centredField(12.0);
  ScanInserter one(1), two(2);
  std::vector<Ray> rays;
  size_t updates_one = 0, updates_two = 0;
  for (const Pose2D& pose : testing::straightPath({0.0, -6.0}, {0.0, 6.0}, 60, 0.3)) {
    scanToRays(world.scan(pose), pose, InsertionOptions(), rays);
    updates_one += one.insert(rays, single);
    updates_two += two.insert(rays, parallel);
  }
  EXPECT_EQ(updates_one, updates_two);
  EXPECT_GT(updates_one, 0u);
  const CellBox box = single.activeBox();
  int differing = 0, reflective = 0;
  for (int y = box.min.y(); y < box.max.y(); ++y) {
    for (int x = box.min.x(); x < box.max.x(); ++x) {
      const CellIndex cell(x, y);
      const int slot = single.window().storageIndex(cell);
      bool same = single.missedBins(cell) == parallel.missedBins(cell) &&
                  single.reflectiveBinsAt(slot) == parallel.reflectiveBinsAt(slot) &&
                  single.reflectiveBins(cell) == single.reflectiveBinsAt(slot);
      for (int bin = 0; bin < single.geometry().thetaBins(); ++bin)
        same = same && single.value(cell, bin) == parallel.value(cell, bin) &&
               single.isReflective(cell, bin) == parallel.isReflective(cell, bin);
      differing += !same;
      reflective += single.reflectiveBinsAt(slot) > 0;
    }
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(reflective, 100);
}

// The paper's core claim (Sec. III): a pane seen only near its normal, and passed through from
// every other direction, stays an obstacle in the RFM but is erased by an occupancy grid.
TEST(GlassPane, StaysOccupiedInTheRfmButIsErasedInThePlainGrid) {
  SyntheticWorld world;
  world.addFramedPane({3.0, -4.0}, {3.0, 4.0});
  world.addWall({6.0, -8.0}, {6.0, 8.0});
  ReflectanceField field = testing::centredField(12.0);
  PlainOccupancyGrid grid(GridOptions(), LogOddsOptions(), testing::regionOfRadius(12.0));
  ScanInserter inserter;
  grid.recenter({0, 0});
  // The robot drives parallel to the pane: it faces it near-normally only briefly.
  std::vector<Ray> rays;
  for (const Pose2D& pose : testing::straightPath({0.0, -6.0}, {0.0, 6.0}, 120, kPi / 2)) {
    scanToRays(world.scan(pose), pose, InsertionOptions(), rays);
    inserter.insert(rays, field);
    grid.insert(rays);
  }
  int rfm_occupied = 0, grid_occupied = 0, cells = 0;
  for (double y = -3.5; y <= 3.5; y += 0.05) {
    const CellIndex cell = field.geometry().cellOf({3.0 + 1e-3, y});
    const CellIndex before = field.geometry().cellOf({3.0 - 1e-3, y});
    ++cells;
    rfm_occupied += field.reflectiveBins(cell) > 0 || field.reflectiveBins(before) > 0;
    grid_occupied += grid.isOccupied(cell) || grid.isOccupied(before);
  }
  EXPECT_GT(rfm_occupied, 0.95 * cells);
  EXPECT_LT(grid_occupied, 0.2 * cells);
}

}  // namespace
}  // namespace rfm
