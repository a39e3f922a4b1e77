#include "reflectance_field_map/core/reflection_removal.h"

#include "reflectance_field_map/core/batch_processor.h"
#include "reflectance_field_map/core/detail/pass_through_detector.h"
#include "reflectance_field_map/core/detail/shared_leap.h"
#include "reflectance_field_map/core/ray_traversal.h"

#include "scenario.h"
#include "test_fields.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace rfm {
namespace {

using detail::PassThroughDetector;
using detail::SharedLeap;
using testing::countLabels;
using testing::driveAlongThePane;
using testing::driveBy;
using testing::fractionAlong;
using testing::LabelCounts;
using testing::Material;
using testing::paneWithWallBehind;
using testing::paneWithWallBehindWorld;
using testing::runScenario;
using testing::ScenarioStep;
using testing::SyntheticWorld;

// The reference for the reflection check: one cell after another over the global cells, no
// leaps. class_of(cell) -> CellClass, reflective_near(cell, bin) -> bool.
template <typename ClassOf, typename ReflectiveNear>
double firstPassThroughDistance(const Ray& ray, const GridGeometry& geometry,
                                double penetration_tolerance, ClassOf&& class_of,
                                ReflectiveNear&& reflective_near) {
  PassThroughDetector detector(ray, geometry, penetration_tolerance);
  forEachCellOnRayWhile(
      ray.origin, ray.end, geometry.inverseResolution(), [&](const CellIndex& cell) {
        return detector.visit(
            cell, class_of(cell), [&](int bin) { return reflective_near(cell, bin); }, class_of);
      });
  return detector.distance();
}

// A ray from `origin` to a return at `end` (m).
Ray returnedRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& end) {
  Ray ray;
  ray.origin = origin;
  ray.end = end;
  ray.angle = std::atan2(end.y() - origin.y(), end.x() - origin.x());
  ray.hit = true;
  return ray;
}

// A wall two cells thick (x = 20 and 21, from y = 20 up), as drift leaves a wall seen twice or a
// surface on a cell boundary draws it, and one more cell, `extra`, static when `extra_static`.
CellClass thickWallAnd(const CellIndex& c, const CellIndex& extra, bool extra_static) {
  if (c == extra) return extra_static ? CellClass::kStatic : CellClass::kFree;
  return (c.x() == 20 || c.x() == 21) && c.y() >= 20 ? CellClass::kStatic : CellClass::kFree;
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
  // Unless the beam has no return: that wall would have returned it (a dropout), and nothing
  // beyond it was observed.
  ray.hit = false;
  EXPECT_NEAR(firstPassThroughDistance(ray, g, 0.15, class_of, always), 1.025 - 0.01, 1e-9);
  ray.hit = true;
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

TEST(FirstPassThroughDistance, AReturnOnStructurePassesTheEndOfAnother) {
  const GridGeometry g(0.05, 180);
  auto never = [](const CellIndex&, int) { return false; };
  // The outer corner of two walls meeting at (20, 20): its obstacle neighbours lie on one side.
  // A ray heading down-right past it crosses its cell near the centre, between the two walls'
  // cells, as a ray past a jamb or a pillar's flank crosses the cell beside the structure in it.
  const CellIndex corner(20, 20);
  const CellIndex far_wall(32, 8);
  bool far_wall_static = true;
  auto class_of = [&](const CellIndex& c) {
    if (c == far_wall) return far_wall_static ? CellClass::kStatic : CellClass::kFree;
    const bool in_walls = (c.y() == corner.y() && c.x() >= corner.x()) ||
                          (c.x() == corner.x() && c.y() <= corner.y());
    return in_walls ? CellClass::kStatic : CellClass::kFree;
  };
  EXPECT_TRUE(detail::endsAStructure(corner, class_of));
  EXPECT_FALSE(detail::endsAStructure(CellIndex(corner.x() + 2, corner.y()), class_of));
  Ray ray = returnedRay(g.cellCenter(CellIndex(8, 32)) + Eigen::Vector2d(0.004, 0.0),
                        g.cellCenter(far_wall));
  // Its return on static structure agrees with the map: nothing blocks it.
  EXPECT_LT(firstPassThroughDistance(ray, g, 0.15, class_of, never), 0.0);
  // Ending where the map has nothing, it passed through the structure: a reflection.
  far_wall_static = false;
  EXPECT_GT(firstPassThroughDistance(ray, g, 0.15, class_of, never), 0.0);
  // Without a return, structure that reflects in its direction would have returned it.
  far_wall_static = true;
  ray.hit = false;
  EXPECT_GT(firstPassThroughDistance(ray, g, 0.15, class_of, never), 0.0);
  // Past the end of a wall drawn two cells thick at a shallow angle, a ray enters at the end
  // cell and crosses cells inside the wall (obstacles on opposite sides of them) before leaving.
  const CellIndex beyond(24, 32);
  bool beyond_static = true;
  auto thick_wall = [&](const CellIndex& c) { return thickWallAnd(c, beyond, beyond_static); };
  EXPECT_TRUE(detail::endsAStructure(CellIndex(21, 20), thick_wall));
  EXPECT_FALSE(detail::endsAStructure(CellIndex(21, 21), thick_wall));
  ray = returnedRay(Eigen::Vector2d(20.3, 16.0) * g.resolution(),
                    g.cellCenter(beyond) - Eigen::Vector2d(0.2, 0.0) * g.resolution());
  EXPECT_LT(firstPassThroughDistance(ray, g, 0.15, thick_wall, never), 0.0);
  beyond_static = false;
  EXPECT_GT(firstPassThroughDistance(ray, g, 0.15, thick_wall, never), 0.0);
  // Inside a surface (obstacles on opposite sides of the cell) a return on structure is cut.
  ray.hit = true;
  ray.origin = {0.01, 0.01};
  ray.end = {3.01, 0.01};
  ray.angle = 0.0;
  const CellIndex column = g.cellOf({1.0, 0.01});
  auto wall_across = [&](const CellIndex& c) {
    return c.x() == column.x() || c == g.cellOf(ray.end) ? CellClass::kStatic : CellClass::kFree;
  };
  EXPECT_NEAR(firstPassThroughDistance(ray, g, 0.15, wall_across, never), 1.025 - 0.01, 1e-9);
}

TEST(FirstPassThroughDistance, AReturnComingOutWhereItWentInPassedBesideTheStructure) {
  const GridGeometry g(0.05, 180);
  auto never = [](const CellIndex&, int) { return false; };
  // The wall two cells thick of thickWallAnd. A ray heading right and down clips its lower end: it
  // goes in at (20, 21), a cell inside the wall (obstacles on opposite sides), and comes out at
  // (22, 20), below the wall's end, on the side it went in.
  const CellIndex far_wall(35, 12);
  bool far_wall_static = true;
  auto class_of = [&](const CellIndex& c) { return thickWallAnd(c, far_wall, far_wall_static); };
  EXPECT_FALSE(detail::endsAStructure(CellIndex(20, 21), class_of));
  auto at = [&](double x, double y) -> Eigen::Vector2d {
    return Eigen::Vector2d(x, y) * g.resolution();
  };
  Ray ray = returnedRay(at(10.0, 27.5), at(35.5, 12.2));
  // Its return on static structure agrees with the map: nothing blocks it.
  EXPECT_LT(firstPassThroughDistance(ray, g, 0.15, class_of, never), 0.0);
  // Ending where the map has nothing, it is cut where it clipped the wall.
  far_wall_static = false;
  EXPECT_GT(firstPassThroughDistance(ray, g, 0.15, class_of, never), 0.0);
  // A ray crossing the wall away from its end comes out on the other side: cut.
  far_wall_static = true;
  ray.origin = at(10.0, 30.5);
  ray.end = g.cellCenter(CellIndex(35, 30));
  ray.angle = 0.0;
  auto wall_and_far_wall = [&](const CellIndex& c) {
    return c == CellIndex(35, 30) ? CellClass::kStatic : class_of(c);
  };
  EXPECT_GT(firstPassThroughDistance(ray, g, 0.15, wall_and_far_wall, never), 0.0);
}

// A wall seen through a glass pane: once the pane is known, rays through it are reflections
// and the wall behind does not enter the map from them.
TEST(ReflectionRemoval, WallSeenThroughGlassIsAReflection) {
  const std::vector<TimedScan> scans = paneWithWallBehind(1);
  const BatchResult motion_only =
      processBatch(scans, testing::scenarioOptions(), BatchOptions{}, BatchMode::kMotionRemoval);
  EXPECT_EQ(countLabels(motion_only.labels).reflection, 0u);
  // The search passes with every scan (as Alg. 3 reads) and with every Nth (the default).
  BatchOptions every_scan;
  every_scan.first_pass_scan_stride = 1;
  every_scan.search_pass_scan_stride = 1;
  for (const BatchOptions& batch : {every_scan, BatchOptions{}}) {
    const bool every = batch.first_pass_scan_stride == 1;
    SCOPED_TRACE(every ? "every scan" : "every Nth scan");
    const BatchResult full =
        processBatch(scans, testing::scenarioOptions(), batch, BatchMode::kFull);
    // With every scan in every pass, the glass found settles (passes of different scans differ
    // by their sampling too).
    if (every) {
      EXPECT_TRUE(full.timings.reflection_converged);
    }
    // Rays through the pane towards the wall: labelled reflection in full mode.
    const LabelCounts with = countLabels(full.labels);
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
  }
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
  const BatchResult full =
      processBatch(scans, testing::scenarioOptions(), BatchOptions{}, BatchMode::kFull);
  const BatchResult basic =
      processBatch(scans, testing::scenarioOptions(), BatchOptions{}, BatchMode::kBasicRfm);
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
  const int image = obstacle_near_virtual_wall(basic.map);
  EXPECT_GT(image, 60);  // of 81 cells along it
  // Two beams of each scan meet the mirror in the cell where its frame begins: the check reads
  // the frame's return there and keeps them. Nothing ever sees through their trace, one or two
  // directions per cell, so it stays (README, Limitations); every other ray is cut.
  EXPECT_LT(obstacle_near_virtual_wall(full.map), 0.6 * image);
  EXPECT_GT(countLabels(full.labels).reflection, 0u);
}

// A facade of framed panes that the robot faces only near a doorway: further along, every ray
// meets the glass obliquely and passes through, so those panes read as free space. Completion
// closes the line between their frames, so the wall seen through them is a reflection too; the
// doorway the robot drove past stays open, and so does a gap longer than the limit.
TEST(ReflectionRemoval, GlassNeverFacedOnAFacadeLineIsCompleted) {
  SyntheticWorld world;
  // Facade at x = 2: a 1 m doorway at |y| < 0.5, then four 1.5 m panes either side; beyond a
  // 2.5 m opening at y in [6.5, 9], one more pane.
  for (double y = 0.5; y < 6.0; y += 1.5) {
    world.addFramedPane({2.0, y}, {2.0, y + 1.5});
    world.addFramedPane({2.0, -y}, {2.0, -y - 1.5});
  }
  world.addFramedPane({2.0, 9.0}, {2.0, 10.5});
  world.addWall({4.5, -20.0}, {4.5, 20.0});
  std::vector<TimedScan> scans;
  for (const auto& step : driveBy({0.0, -1.5}, {0.0, 1.5}, kPi / 2)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  for (const auto& step : driveBy({-2.0, 1.5}, {-2.0, -1.5}, -kPi / 2)) {
    scans.push_back(world.timedScan(step.robot, 0.025 * scans.size()));
  }
  MapperOptions options = testing::scenarioOptions();
  options.active_region.active_region_radius = 15.0;
  const BatchResult completed = processBatch(scans, options, BatchOptions{}, BatchMode::kFull);
  options.reflection_removal.glass_completion_max_gap = 0.0;
  const BatchResult not_completed = processBatch(scans, options, BatchOptions{}, BatchMode::kFull);

  // Rays ending on the wall behind, by where they cross the facade's line.
  struct Share {
    size_t rays = 0, kept = 0;
    double kept_fraction() const { return rays == 0 ? 0.0 : static_cast<double>(kept) / rays; }
  };
  auto wall_rays = [&](const BatchResult& result, double min_abs_y, double max_abs_y) {
    Share share;
    for (size_t s = 0; s < scans.size(); ++s) {
      const LaserScan2D& scan = scans[s].scan;
      const Pose2D& sensor = scans[s].sensor_pose;
      for (size_t beam = 0; beam < scan.ranges.size(); ++beam) {
        const double angle = sensor.yaw + scan.angle_min + beam * scan.angle_increment;
        const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
        const Eigen::Vector2d end = sensor.position + scan.ranges[beam] * direction;
        if (!std::isfinite(scan.ranges[beam]) || std::abs(end.x() - 4.5) > 0.05) continue;
        const double crossing =
            sensor.position.y() + direction.y() * (2.0 - sensor.position.x()) / direction.x();
        if (std::abs(crossing) < min_abs_y || std::abs(crossing) > max_abs_y) continue;
        ++share.rays;
        share.kept += result.labels[s][beam] == RayLabel::kKept;
      }
    }
    return share;
  };
  // Through the panes never faced (the robot faced |y| < 1.6 at most).
  const Share unfaced = wall_rays(completed, 2.1, 6.4);
  ASSERT_GT(unfaced.rays, 1000u);
  EXPECT_LT(unfaced.kept_fraction(), 0.05);
  EXPECT_GT(wall_rays(not_completed, 2.1, 6.4).kept_fraction(), 0.5);
  // Through the doorway the robot drove past: kept, as without completion.
  const Share doorway = wall_rays(completed, 0.0, 0.4);
  ASSERT_GT(doorway.rays, 1000u);
  EXPECT_GT(doorway.kept_fraction(), 0.9);
  EXPECT_NEAR(doorway.kept_fraction(), wall_rays(not_completed, 0.0, 0.4).kept_fraction(), 0.01);
  // The map: the unfaced panes are glass, the doorway and the opening longer than the limit
  // are not.
  auto glass_along = [&](double from_y, double to_y) {
    const GridGeometry g(0.05, 180);
    int glass = 0, total = 0;
    for (double y = from_y; y <= to_y; y += 0.05, ++total) {
      glass += completed.map.get(g.cellOf({2.0 - 1e-3, y})) == CellClass::kGlass ||
               completed.map.get(g.cellOf({2.0 + 1e-3, y})) == CellClass::kGlass;
    }
    return static_cast<double>(glass) / total;
  };
  EXPECT_GT(glass_along(2.1, 3.4), 0.9);
  EXPECT_GT(glass_along(-6.4, -5.1), 0.9);
  EXPECT_EQ(glass_along(-0.4, 0.4), 0.0);
  EXPECT_EQ(glass_along(6.6, 8.9), 0.0);
}

// Beams every 0.25 deg over +-35 deg from near the origin, every other one to x = 4 m and the
// others on to 4.6 m: a beam let through beside a pane at x = 2 m crosses the cell where its
// neighbour, cut at the pane, took a hit, so that cell's bin turns from a hit into a miss.
struct FanScan {
  Eigen::Vector2d origin{0.02, 0.03};
  double first_angle = -0.611;
  double increment = 0.0043633;
  std::vector<Ray> rays;
};

FanScan fanTowardsPanes() {
  FanScan scan;
  for (uint32_t k = 0; k < 281; ++k) {
    const double angle = scan.first_angle + k * scan.increment;
    const double wall_x = k % 2 == 0 ? 3.98 : 4.6;
    Ray ray;
    ray.origin = scan.origin;
    ray.end = scan.origin +
              (wall_x / std::cos(angle)) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    ray.angle = wrapTwoPi(angle);
    ray.hit = true;
    ray.beam = k;
    scan.rays.push_back(ray);
  }
  return scan;
}

// Panes at x = 2 m between y = -1.0 and 0.43 m, 0.3 m wide with 0.15 m gaps, found glass after
// the scans went in: many theta bins hold beams cut at a pane and beams let through. Returns the
// new glass.
CellBox classifyPanes(const ReflectanceField& field, ActiveClasses& classes) {
  const GridGeometry& geometry = field.geometry();
  ClassifiedRegion region;
  region.box = field.window().box();
  region.classes.assign(static_cast<size_t>(region.box.width()) * region.box.height(),
                        CellClass::kFree);
  for (double y = -1.0; y <= 0.43; y += 0.5 * geometry.resolution()) {
    if (std::fmod(y + 1.0, 0.45) > 0.3) continue;
    region.classes[region.box.indexOf(geometry.cellOf({2.0, y}))] = CellClass::kGlass;
  }
  return classes.replace(region, nullptr);
}

// Takes back every kept scan's evidence beyond `new_glass` at once (as removeMotion() does).
void revertWhole(ReflectionRemover& remover, const CellBox& new_glass, ScanInserter& inserter,
                 ReflectanceField& field) {
  remover.startRevert(new_glass);
  remover.revertSome(std::numeric_limits<size_t>::max(), 1, inserter, field);
}

// Bins and reflective masks of the window that differ between two fields.
size_t differingBins(const ReflectanceField& a, const ReflectanceField& b) {
  size_t differing = 0;
  const CellBox box = a.window().box();
  for (int y = box.min.y(); y < box.max.y(); ++y) {
    for (int x = box.min.x(); x < box.max.x(); ++x) {
      const int slot = a.window().storageIndex({x, y});
      differing += a.reflectiveBinsAt(slot) != b.reflectiveBinsAt(slot);
      for (int bin = 0; bin < a.geometry().thetaBins(); ++bin)
        differing += a.value({x, y}, bin) != b.value({x, y}, bin);
    }
  }
  return differing;
}

// A kept scan that crossed panes classified afterwards loses exactly its evidence beyond them:
// the field after the whole revert holds what the scan would have left cut at the panes. The
// panes end inside some theta bins' fans, so their cells beyond keep the misses of the beams that
// went past (the updates are de-duplicated per bin).
TEST(ReflectionRemoval, RevertBehindNewGlassLeavesWhatTheScanCutAtItWouldHave) {
  ReflectanceField field = testing::centredField(6.0);
  ReflectanceField reference = testing::centredField(6.0);
  const GridGeometry& geometry = field.geometry();
  GlobalMap2D map;
  ActiveClasses classes(field.window(), map, 0);
  const ReflectionRemovalOptions options;
  ReflectionRemover remover(options, field, classes);
  ScanInserter inserter;

  const FanScan scan = fanTowardsPanes();
  inserter.insert(scan.rays, field);
  remover.keep(scan.rays, scan.origin, scan.first_angle, scan.increment, 0.0);
  const CellBox new_glass = classifyPanes(field, classes);
  ASSERT_FALSE(new_glass.empty());
  revertWhole(remover, new_glass, inserter, field);

  std::vector<Ray> cut_rays = scan.rays;
  std::vector<RayLabel> labels(cut_rays.size(), RayLabel::kNoReturn);
  const size_t cut = remover.cut(cut_rays, labels, nullptr);
  EXPECT_GT(cut, 50u);
  EXPECT_LT(cut, cut_rays.size() - 50);
  inserter.insert(cut_rays, reference);

  EXPECT_EQ(differingBins(field, reference), 0u);
  size_t changed = 0;
  const CellBox box = field.window().box();
  const int beyond_panes = geometry.cellOf({2.1, 0.0}).x();
  for (int y = box.min.y(); y < box.max.y(); ++y)
    for (int x = beyond_panes + 1; x < box.max.x(); ++x)
      for (int bin = 0; bin < geometry.thetaBins(); ++bin)
        changed += reference.value({x, y}, bin) != 0;
  EXPECT_GT(changed, 100u);  // beyond the pane, the beams that passed it left their evidence
}

// A revert spread over later scans takes back what the whole revert takes back, scan by scan;
// a scan still to revert stays kept past the buffer's size until it is reverted.
TEST(ReflectionRemoval, ARevertInPartsTakesBackWhatTheWholeRevertDoes) {
  ReflectanceField whole_field = testing::centredField(6.0);
  ReflectanceField parts_field = testing::centredField(6.0);
  GlobalMap2D whole_map, parts_map;
  ActiveClasses whole_classes(whole_field.window(), whole_map, 0);
  ActiveClasses parts_classes(parts_field.window(), parts_map, 0);
  ReflectionRemovalOptions options;
  options.scan_buffer_size = 2;
  ReflectionRemover whole(options, whole_field, whole_classes);
  ReflectionRemover parts(options, parts_field, parts_classes);
  ScanInserter inserter;

  // Two scans from the same place, both kept, then the panes are found.
  const FanScan scan = fanTowardsPanes();
  for (int i = 0; i < 2; ++i) {
    inserter.insert(scan.rays, whole_field);
    whole.keep(scan.rays, scan.origin, scan.first_angle, scan.increment, 0.0);
    inserter.insert(scan.rays, parts_field);
    parts.keep(scan.rays, scan.origin, scan.first_angle, scan.increment, 0.0);
  }
  const CellBox new_glass = classifyPanes(whole_field, whole_classes);
  const CellBox parts_glass = classifyPanes(parts_field, parts_classes);
  ASSERT_EQ(parts_glass.min, new_glass.min);
  ASSERT_EQ(parts_glass.max, new_glass.max);
  // Two scans after the pass, looking the other way (their updates and the revert's touch
  // different bins, so the order they go in does not matter), fill the buffer past the marked
  // scans before any of those is reverted.
  FanScan behind = scan;
  for (Ray& ray : behind.rays) {
    ray.end = 2.0 * ray.origin - ray.end;
    ray.angle = wrapTwoPi(ray.angle + M_PI);
  }
  behind.first_angle += M_PI;

  revertWhole(whole, new_glass, inserter, whole_field);
  EXPECT_FALSE(whole.revertPending());
  parts.startRevert(parts_glass);
  for (int i = 0; i < 2; ++i) {
    inserter.insert(behind.rays, whole_field);
    whole.keep(behind.rays, behind.origin, behind.first_angle, behind.increment, 0.0);
    inserter.insert(behind.rays, parts_field);
    parts.keep(behind.rays, behind.origin, behind.first_angle, behind.increment, 0.0);
  }
  EXPECT_NE(differingBins(whole_field, parts_field), 0u);
  for (int part = 0; part < 2; ++part) {  // a budget of one ray: one scan a part
    ASSERT_TRUE(parts.revertPending()) << "part " << part;
    parts.revertSome(1, 1, inserter, parts_field);
  }
  EXPECT_FALSE(parts.revertPending());
  EXPECT_EQ(differingBins(whole_field, parts_field), 0u);
}

// Online: the live mapper labels rays through glass it already knows as reflections at insertion.
TEST(ReflectionRemoval, OnlineScansThroughKnownGlassAreReflections) {
  SyntheticWorld world = paneWithWallBehindWorld();
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveAlongThePane());
  const TimedScan scan = world.timedScan({{0.0, 0.0}, 0.0});
  const ScanUpdate update = mapper.addScan(scan);
  size_t reflections = 0;
  for (RayLabel l : update.labels)
    reflections += l == RayLabel::kReflection;
  EXPECT_GT(reflections, 100u);
  EXPECT_GT(mapper.stats().reflection_rays, 0u);
  // The labels the node publishes keep every beam the insertion cut, whatever the map says, and
  // judge the others against the map. A beam the map keeps, marked cut, shows the first part.
  const std::vector<RayLabel> by_map = mapper.labelScan(scan);
  ScanUpdate cut = update;
  const auto kept = std::find(by_map.begin(), by_map.end(), RayLabel::kKept);
  ASSERT_NE(kept, by_map.end());
  cut.labels[kept - by_map.begin()] = RayLabel::kReflection;
  const std::vector<RayLabel> published = mapper.labelAddedScan(scan, cut);
  ASSERT_EQ(published.size(), cut.labels.size());
  for (size_t i = 0; i < published.size(); ++i) {
    EXPECT_EQ(published[i],
              cut.labels[i] == RayLabel::kReflection ? RayLabel::kReflection : by_map[i])
        << "beam " << i;
  }
}

// A return whose whole ray the insertion checked keeps that check's answer in the published
// labels: the check read the classes the labels read, so it is not run again. A return the
// region cut short is checked whole when labelled.
TEST(ReflectionRemoval, LabelsTakeTheInsertionsAnswerForTheWholeRaysItChecked) {
  SyntheticWorld world = paneWithWallBehindWorld();
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveAlongThePane());
  const TimedScan scan = world.timedScan({{0.0, 0.0}, 0.0});
  const ScanUpdate update = mapper.addScan(scan);
  ASSERT_EQ(update.checked_returns.size(), scan.scan.ranges.size());
  // Pretend the insertion let the beams through the pane pass: checked, they stay unchecked.
  ScanUpdate let_pass = update;
  size_t through_pane = 0;
  for (size_t i = 0; i < let_pass.labels.size(); ++i) {
    if (let_pass.labels[i] != RayLabel::kReflection) continue;
    EXPECT_EQ(let_pass.checked_returns[i], 1) << "beam " << i;
    let_pass.labels[i] = RayLabel::kKept;
    ++through_pane;
  }
  ASSERT_GT(through_pane, 100u);
  const std::vector<RayLabel> published = mapper.labelAddedScan(scan, let_pass);
  EXPECT_EQ(std::count(published.begin(), published.end(), RayLabel::kReflection), 0);
  // Not marked checked, they are checked when labelled, and found passing through the pane.
  std::fill(let_pass.checked_returns.begin(), let_pass.checked_returns.end(), 0);
  const std::vector<RayLabel> rechecked = mapper.labelAddedScan(scan, let_pass);
  EXPECT_GE(
      static_cast<size_t>(std::count(rechecked.begin(), rechecked.end(), RayLabel::kReflection)),
      through_pane);
}

// The robot maps a wall, then its laser returns nothing from it (a dark stretch, dropouts): the
// beams clear up to the clearing distance, but only up to the wall. The cells behind it stay
// unknown, and the node publishes the beams as NO_RETURN.
TEST(ReflectionRemoval, BeamsWithoutAReturnClearNothingBehindAWall) {
  SyntheticWorld world;
  world.addWall({2.0, -6.0}, {2.0, 6.0});
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveBy({0.0, -3.0}, {0.0, 3.0}, 0.0));
  const CellIndex behind = mapper.field().geometry().cellOf({2.6, 0.0});
  ASSERT_EQ(mapper.cellClass(behind), CellClass::kUnknown);
  for (int i = 0; i < 40; ++i) {
    TimedScan dark = world.timedScan({{0.0, 0.0}, 0.0}, 10.0 + 0.025 * i);
    std::fill(dark.scan.ranges.begin(), dark.scan.ranges.end(),
              std::numeric_limits<float>::infinity());
    const ScanUpdate update = mapper.addScan(dark);
    ASSERT_TRUE(update.error.empty()) << update.error;
    const std::vector<RayLabel> published = mapper.labelAddedScan(dark, update);
    EXPECT_EQ(std::count(published.begin(), published.end(), RayLabel::kNoReturn),
              static_cast<long>(published.size()));
  }
  mapper.removeMotion();
  EXPECT_EQ(mapper.cellClass(behind), CellClass::kUnknown);
  EXPECT_EQ(mapper.cellClass(mapper.field().geometry().cellOf({1.0, 0.0})), CellClass::kFree);
  EXPECT_TRUE(isObstacle(mapper.cellClass(mapper.field().geometry().cellOf({2.0, 0.0}))));
}

// A wall seen from one place only returns in a few directions: too few to say it would have
// returned a ray from elsewhere, which a corner or pose error may let pass. It blocks rays only
// once it is reflective over static_blocking_min_angle.
TEST(ReflectionRemoval, StaticCellsSeenFromOnePlaceBlockNothing) {
  SyntheticWorld world;
  world.addWall({2.0, -0.3}, {2.0, 0.3});
  SyntheticWorld beyond;
  beyond.addWall({4.0, -6.0}, {4.0, 6.0});
  const Pose2D elsewhere{{0.0, -1.5}, 0.0};
  for (double min_angle : {0.0, 16.0 * kPi / 180.0}) {
    MapperOptions options = testing::scenarioOptions();
    options.reflection_removal.static_blocking_min_angle = min_angle;
    Mapper mapper(options);
    runScenario(mapper, world, std::vector<ScenarioStep>(40, ScenarioStep{{{0.0, 0.0}, 0.0}, {}}));
    mapper.removeMotion();
    const CellIndex wall = mapper.field().geometry().cellOf({2.0 + 1e-3, 0.0});
    ASSERT_EQ(mapper.cellClass(wall), CellClass::kStatic);
    ASSERT_LT(mapper.field().reflectiveBins(wall), 8);
    // Rays from elsewhere through where the wall was, to a wall beyond.
    const std::vector<RayLabel> labels = mapper.labelScan(beyond.timedScan(elsewhere));
    const size_t through = std::count(labels.begin(), labels.end(), RayLabel::kReflection);
    if (min_angle == 0.0) {
      EXPECT_GT(through, 5u);
    } else {
      EXPECT_EQ(through, 0u);
    }
  }
}

// A wall's end cell beside a pane, static, reflective over 20 deg next to a ray's direction but
// not in it: the ray leaves through the pane's end, as the pane's reflections do, and is cut
// there. The same cell in the middle of a wall lets it pass (a wall grazed at a shallow angle is
// hit in neighbouring directions), and beside the pane too once it reflected in the ray's own
// direction.
TEST(ReflectionRemoval, StaticCellsBesideAPaneLetRaysPassOnlyInTheirOwnDirection) {
  for (const bool pane_beside : {false, true}) {
    for (const bool own_direction : {false, true}) {
      ReflectanceField field = testing::centredField(4.0);
      const GridGeometry& geometry = field.geometry();  // 2 deg bins
      Ray ray;
      ray.origin = {0.01, 0.025};
      ray.end = {3.5, 0.025};
      ray.angle = 0.0;
      ray.hit = true;
      const int ray_bin = geometry.binOf(ray.angle);
      const CellIndex end_of_wall = geometry.cellOf({2.01, 0.025});
      const int first_bin = own_direction ? ray_bin : ray_bin + 1;
      for (int bin = first_bin; bin < first_bin + 10; ++bin) {
        for (int i = 0; i < 4; ++i)
          field.applyHit(end_of_wall, bin);
      }
      GlobalMap2D map;
      ActiveClasses classes(field.window(), map, 0);
      ClassifiedRegion region;
      region.box = field.window().box();
      region.classes.assign(static_cast<size_t>(region.box.width()) * region.box.height(),
                            CellClass::kFree);
      for (int dy = -10; dy <= 10; ++dy) {
        const CellIndex cell(end_of_wall.x(), end_of_wall.y() + dy);
        const bool pane = pane_beside && dy > 0;
        region.classes[region.box.indexOf(cell)] = pane ? CellClass::kGlass : CellClass::kStatic;
      }
      classes.replace(region, nullptr);
      const ReflectionRemover remover(ReflectionRemovalOptions(), field, classes);
      double through = -1.0;
      remover.passThroughDistances(&ray, 1, &through);
      const std::string where = std::string(pane_beside ? "beside a pane" : "inside a wall") +
                                (own_direction ? ", reflective in the ray's direction" : "");
      if (pane_beside && !own_direction) {
        EXPECT_NEAR(through, geometry.cellCenter(end_of_wall).x() - ray.origin.x(), 1e-9) << where;
      } else {
        EXPECT_LT(through, 0.0) << where;
      }
    }
  }
}

// Eight neighbouring beams leap together on the middle one's clearance: the fan widens with
// distance, so the group must stop before the outermost beam reaches a blocking cell that the
// middle beam passes three cells away.
TEST(SharedLeap, StopsBeforeAnyRayOfTheGroupPassesABlockingCell) {
  const GridGeometry g(0.05, 180);
  const Eigen::Vector2d origin(0.01, 0.01);
  Ray rays[8];
  std::optional<PassThroughDetector> detectors[8];
  for (int i = 0; i < 8; ++i) {
    rays[i].origin = origin;
    rays[i].angle = (-0.875 + 0.25 * i) * kPi / 180.0;
    rays[i].end = origin + 12.0 * Eigen::Vector2d(std::cos(rays[i].angle), std::sin(rays[i].angle));
    rays[i].hit = true;
    detectors[i].emplace(rays[i], g, 0.15);
  }
  // One blocking cell on the outermost beam, 10 m out.
  const CellIndex blocker = g.cellOf(origin + 10.0 * detectors[7]->direction());
  const CellBox box{{-20, -100}, {300, 100}};
  ClearanceMap clearance(0);
  clearance.compute(box, [&](int dx, int dy) { return box.min + CellIndex(dx, dy) != blocker; });

  SharedLeap group;
  ASSERT_TRUE(group.start(rays, detectors, 0, 8));
  while (group.leap(clearance, g)) {
  }
  // Far out, clear of the blocker, on every beam: the leaps pass no blocking cell.
  EXPECT_GT(group.reached(), 5.0);
  for (int i = 0; i < 8; ++i) {
    forEachCellOnRayWhile(origin, origin + group.reached() * detectors[i]->direction(),
                          g.inverseResolution(), [&](const CellIndex& cell) {
                            EXPECT_NE(cell, blocker) << "ray " << i;
                            return true;
                          });
  }
  // Without it the group leaps on to the last candidate.
  ClearanceMap open(0);
  open.compute(box, [](int, int) { return true; });
  ASSERT_TRUE(group.start(rays, detectors, 0, 8));
  while (group.leap(open, g)) {
  }
  EXPECT_DOUBLE_EQ(group.reached(), 12.0 - 0.15);
  // Rays from different origins share nothing.
  rays[3].origin.x() += 0.01;
  EXPECT_FALSE(group.start(rays, detectors, 0, 8));
  EXPECT_EQ(group.reached(), 0.0);
}

// The mapper's reflection check leaps over cells that cannot block, neighbouring beams first
// together (their fan widens with distance): it must decide every beam as a walk over every cell
// would. Scans from around a pane's end, near and far, put fans across the pane's edge.
TEST(ReflectionRemoval, LeapingCheckDecidesEveryBeamAsAFullWalk) {
  SyntheticWorld world = paneWithWallBehindWorld();
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveAlongThePane());
  mapper.removeMotion();
  const GridGeometry& g = mapper.field().geometry();
  const int bins = g.thetaBins();
  const double tolerance = testing::scenarioOptions().reflection_removal.penetration_tolerance;
  auto class_of = [&](const CellIndex& c) { return mapper.cellClass(c); };
  const int static_blocking_min_bins = static_cast<int>(std::ceil(
      testing::scenarioOptions().reflection_removal.static_blocking_min_angle / g.binWidth() -
      1e-9));
  auto reflective_near = [&](const CellIndex& c, int bin) {
    return detail::staticCellLetsPass(mapper.field().reflectiveMask(c), mapper.field().maskWords(),
                                      bin, bins, static_blocking_min_bins,
                                      [&] { return detail::besideGlassOrMetal(c, class_of); });
  };
  size_t reflections = 0, beams = 0;
  for (const Pose2D& robot : {Pose2D{{0.0, 2.0}, 0.3}, Pose2D{{0.0, 4.5}, -0.6},
                              Pose2D{{-1.5, 3.0}, 0.0}, Pose2D{{1.0, 5.0}, -1.1}}) {
    const TimedScan scan = world.timedScan(robot);
    const std::vector<RayLabel> labels = mapper.labelScan(scan);
    std::vector<Ray> rays;
    scanToRays(scan.scan, scan.sensor_pose, testing::scenarioOptions().insertion, rays);
    for (const Ray& ray : rays) {
      if (!ray.hit) continue;
      const bool through =
          firstPassThroughDistance(ray, g, tolerance, class_of, reflective_near) >= 0.0;
      EXPECT_EQ(labels[ray.beam] == RayLabel::kReflection, through)
          << "beam " << ray.beam << " from (" << robot.position.transpose() << ")";
      reflections += through;
      ++beams;
    }
  }
  // Both kinds of beam occur: the wall seen through the pane and around its end.
  EXPECT_GT(reflections, 100u);
  EXPECT_GT(beams - reflections, 100u);
}

}  // namespace
}  // namespace rfm
