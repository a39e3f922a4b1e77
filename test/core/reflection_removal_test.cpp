#include "reflectance_field_map/core/batch_processor.h"
#include "reflectance_field_map/core/ray_classification.h"

#include "scenario.h"

#include <gtest/gtest.h>

namespace rfm {
namespace {

using testing::driveBy;
using testing::fractionAlong;
using testing::Material;
using testing::runScenario;
using testing::SyntheticWorld;

struct LabelCounts {
  size_t kept = 0, motion = 0, reflection = 0, no_return = 0;
};

LabelCounts count(const std::vector<std::vector<RayLabel>>& labels) {
  LabelCounts c;
  for (const auto& scan : labels) {
    for (RayLabel l : scan) {
      c.kept += l == RayLabel::kKept;
      c.motion += l == RayLabel::kMotion;
      c.reflection += l == RayLabel::kReflection;
      c.no_return += l == RayLabel::kNoReturn;
    }
  }
  return c;
}

TEST(FirstPassThroughDistance, StopsWhereTheRayCrossesGlassOrAStaticSurface) {
  const GridGeometry g(0.05, 180);
  Ray ray;
  ray.origin = {0.01, 0.01};
  ray.end = {3.01, 0.01};
  ray.angle = 0.0;
  ray.hit = true;
  // A pane across the ray: the column of cells at x = 1.0 m.
  const CellIndex glass = g.cellOf({1.0, 0.01});
  CellClass glass_class = CellClass::kGlass;
  auto class_of = [&](const CellIndex& c) {
    return c.x() == glass.x() ? glass_class : CellClass::kFree;
  };
  auto never = [](const CellIndex&, int) { return false; };
  auto always = [](const CellIndex&, int) { return true; };
  EXPECT_NEAR(firstPassThroughDistance(ray, g, 0.15, class_of, never), 1.025 - 0.01, 1e-9);
  // Glass is passed through even in a direction it sometimes returns (a bump tilted it).
  EXPECT_NEAR(firstPassThroughDistance(ray, g, 0.15, class_of, always), 1.025 - 0.01, 1e-9);
  // A static cell that returns rays in this direction is a wall grazed, not passed through.
  glass_class = CellClass::kStatic;
  EXPECT_LT(firstPassThroughDistance(ray, g, 0.15, class_of, always), 0.0);
  EXPECT_GT(firstPassThroughDistance(ray, g, 0.15, class_of, never), 0.0);
  glass_class = CellClass::kGlass;
  // Ending just behind the glass (within the tolerance) is the glass's own return.
  ray.end = {1.1, 0.01};
  EXPECT_LT(firstPassThroughDistance(ray, g, 0.15, class_of, never), 0.0);
  // Grazing along a wall: every cell after the first obstacle is an obstacle up to the end.
  ray.end = {3.01, 0.01};
  auto wall_from_one_metre = [&](const CellIndex& c) {
    return c.x() >= glass.x() ? CellClass::kStatic : CellClass::kFree;
  };
  EXPECT_LT(firstPassThroughDistance(ray, g, 0.15, wall_from_one_metre, never), 0.0);
  // A lone glass cell (a surface the field has barely seen) is crossed; the tip of a structure
  // (a pane ending at the ray) is not: the ray passes beside it through the empty part.
  auto lone_cell = [&](const CellIndex& c) {
    return c == glass ? CellClass::kGlass : CellClass::kFree;
  };
  EXPECT_GT(firstPassThroughDistance(ray, g, 0.15, lone_cell, never), 0.0);
  auto pane_ending_here = [&](const CellIndex& c) {
    return c.x() == glass.x() && c.y() >= glass.y() ? CellClass::kGlass : CellClass::kFree;
  };
  EXPECT_LT(firstPassThroughDistance(ray, g, 0.15, pane_ending_here, never), 0.0);
}

// A wall seen through a glass pane: once the pane is known, rays through it are reflections
// and the wall behind does not enter the map from them.
TEST(ReflectionRemoval, WallSeenThroughGlassIsAReflection) {
  SyntheticWorld world;
  world.addFramedPane({2.0, -3.0}, {2.0, 3.0});
  world.addWall({4.0, -6.0}, {4.0, 6.0});
  std::vector<TimedScan> scans;
  for (const auto& step : driveBy({0.0, -4.0}, {0.0, 4.0}, kPi / 2)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  const BatchResult full = processBatch(scans, testing::scenarioOptions(), BatchMode::kFull);
  const BatchResult motion_only =
      processBatch(scans, testing::scenarioOptions(), BatchMode::kMotionRemoval);
  // Rays through the pane towards the wall: labelled reflection in full mode.
  const LabelCounts with = count(full.labels), without = count(motion_only.labels);
  EXPECT_EQ(without.reflection, 0u);
  EXPECT_GT(with.reflection, 0.3 * (with.kept + with.reflection + with.motion));
  // The pane itself is kept.
  const GridGeometry g(0.05, 180);
  int glass = 0, total = 0;
  for (double y = -2.8; y <= 2.8; y += 0.05, ++total) {
    glass += isObstacle(full.map.get(g.cellOf({2.0 + 1e-3, y}))) ||
             isObstacle(full.map.get(g.cellOf({2.0 - 1e-3, y})));
  }
  EXPECT_GT(glass, 0.9 * total);
  // The wall behind, seen only through the glass, is not an obstacle in the full map.
  int wall = 0;
  total = 0;
  for (double y = -2.0; y <= 2.0; y += 0.05, ++total) {
    wall += isObstacle(full.map.get(g.cellOf({4.0 + 1e-3, y}))) ||
            isObstacle(full.map.get(g.cellOf({4.0 - 1e-3, y})));
  }
  EXPECT_LT(wall, 0.1 * total);
  EXPECT_TRUE(full.timings.reflection_converged);
}

// A mirror returns near its normal and otherwise folds the ray into a virtual image behind it.
TEST(ReflectionRemoval, MirrorImageIsRemoved) {
  SyntheticWorld world;
  world.addWall({2.5, -3.0}, {2.5, -2.94});  // frames
  world.segments.push_back({{2.5, -2.94}, {2.5, 2.94}, Material::kMirror});
  world.addWall({2.5, 2.94}, {2.5, 3.0});
  world.addWall({-3.0, -6.0}, {-3.0, 6.0});  // the wall the mirror shows behind itself
  std::vector<TimedScan> scans;
  for (const auto& step : driveBy({0.0, -4.0}, {0.0, 4.0}, 0.0)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  const BatchResult full = processBatch(scans, testing::scenarioOptions(), BatchMode::kFull);
  const BatchResult basic = processBatch(scans, testing::scenarioOptions(), BatchMode::kBasicRfm);
  const GridGeometry g(0.05, 180);
  // The virtual wall would appear at x = 2.5 + (2.5 + 3.0) = 8.0.
  auto obstacle_near_virtual_wall = [&](const GlobalMap2D& map) {
    int n = 0;
    for (double y = -2.0; y <= 2.0; y += 0.05) {
      for (double dx = -0.1; dx <= 0.1; dx += 0.05)
        n += isObstacle(map.get(g.cellOf({8.0 + dx, y})));
    }
    return n;
  };
  EXPECT_GT(obstacle_near_virtual_wall(basic.map), 20);
  EXPECT_EQ(obstacle_near_virtual_wall(full.map), 0);
  EXPECT_GT(count(full.labels).reflection, 0u);
}

// Two parallel panes: the paper reports Alg. 3 may not converge. It must end, keeping both.
TEST(ReflectionRemoval, TwoParallelPanesTerminateWithBothKept) {
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
  MapperOptions options = testing::scenarioOptions();
  options.reflection_removal.max_reflection_iterations = 6;
  const BatchResult full = processBatch(scans, options, BatchMode::kFull);
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

// Online: the live mapper labels rays through glass it already knows as reflections at insertion.
TEST(ReflectionRemoval, OnlineScansThroughKnownGlassAreReflections) {
  SyntheticWorld world;
  world.addFramedPane({2.0, -3.0}, {2.0, 3.0});
  world.addWall({4.0, -6.0}, {4.0, 6.0});
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveBy({0.0, -4.0}, {0.0, 4.0}, kPi / 2));
  const ScanUpdate update = mapper.addScan(world.timedScan({{0.0, 0.0}, 0.0}));
  size_t reflections = 0;
  for (RayLabel l : update.labels)
    reflections += l == RayLabel::kReflection;
  EXPECT_GT(reflections, 100u);
  EXPECT_GT(mapper.stats().reflection_rays, 0u);
}

}  // namespace
}  // namespace rfm
