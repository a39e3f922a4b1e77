// Procedural scenes: reproducible from their seed and their file, loadable, varied, and made of
// walks that never pass through walls, one another or the robot.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "reflectance_field_map/sim/navigation_grid.h"
#include "reflectance_field_map/sim/random_scene.h"
#include "reflectance_field_map/sim/scene.h"
#include "reflectance_field_map/sim/simulator.h"

namespace rfm::sim {
namespace {

TEST(NavigationGridTest, ClearancePathsAndSightAroundAWall) {
  World world;
  world.addSegment({5, -3}, {5, 3}, Material::kDiffuse);  // a wall across the way
  const NavigationGrid grid(world, {0, -5}, {10, 5}, 0.1);
  EXPECT_NEAR(grid.clearance({3.0, 0.0}), 2.0, 0.11);
  EXPECT_LT(grid.clearance({5.0, 0.0}), 0.06);
  EXPECT_LT(grid.clearance({5.0, 4.5}), 0.5);  // the box's edge counts as a wall
  EXPECT_FALSE(grid.lineClear({2, 0}, {8, 0}, 0.3));
  EXPECT_TRUE(grid.lineClear({2, 0}, {3, 0}, 0.3));

  const auto path = grid.path({2, 0}, {8, 0}, 0.4);
  ASSERT_TRUE(path.has_value());
  EXPECT_TRUE(path->front().isApprox(Eigen::Vector2d(2, 0)));
  EXPECT_TRUE(path->back().isApprox(Eigen::Vector2d(8, 0)));
  double length = 0.0;
  for (std::size_t i = 0; i + 1 < path->size(); ++i) {
    EXPECT_TRUE(grid.lineClear((*path)[i], (*path)[i + 1], 0.4));
    length += ((*path)[i + 1] - (*path)[i]).norm();
  }
  EXPECT_GT(length, 6.0 + 2.0);                              // round an end of the wall
  EXPECT_LT(path->size(), 8u);                               // corners only
  EXPECT_FALSE(grid.path({2, 0}, {8, 0}, 1.2).has_value());  // the gaps are 2 m wide
  // Kept below y = 2, the path rounds the wall's bottom end; kept within |y| < 2, there is none.
  const auto below =
      grid.path({2, 0}, {8, 0}, 0.4, [](const Eigen::Vector2d& p) { return p.y() < 2.0; });
  ASSERT_TRUE(below.has_value());
  for (const Eigen::Vector2d& corner : *below)
    EXPECT_LT(corner.y(), 2.0);
  EXPECT_FALSE(
      grid.path({2, 0}, {8, 0}, 0.4, [](const Eigen::Vector2d& p) { return std::abs(p.y()) < 2.0; })
          .has_value());
}

TEST(RandomSceneTest, TheSameSeedDrawsTheSameFileAndOtherSeedsOthers) {
  RandomSceneOptions options;
  options.seed = 11;
  options.duration = 20.0;
  const std::string a = generateRandomScene(options).yaml;
  EXPECT_EQ(a, generateRandomScene(options).yaml);
  options.seed = 12;
  EXPECT_NE(a, generateRandomScene(options).yaml);
  options.setup = "no_such_setup";
  EXPECT_THROW(generateRandomScene(options), std::invalid_argument);
  options.setup = "wheelchair";
  options.duration = 1.0;
  EXPECT_THROW(generateRandomScene(options), std::invalid_argument);
}

// Whether two footprints overlap anywhere along the scene, checked every 20 ms.
bool overlapAnywhere(const Pedestrian& a, const Pedestrian& b, double duration) {
  for (double t = 0.0; t <= duration; t += 0.02) {
    const auto p = a.positionAt(t), q = b.positionAt(t);
    if (p && q && (*p - *q).norm() < a.spec().radius + b.spec().radius - 1e-3) return true;
  }
  return false;
}

TEST(RandomSceneTest, ScenesLoadWithSolidPeopleAndTheirSetup) {
  std::set<std::string> layouts;
  int glass_surfaces = 0, people = 0, legged = 0;
  for (const std::uint32_t seed : {1u, 2u, 3u, 1001u, 1002u, 1003u}) {
    SCOPED_TRACE(seed);
    RandomSceneOptions options;
    options.seed = seed;
    options.setup = seed % 2 ? "sick180" : "wheelchair";
    const RandomScene random = generateRandomScene(options);
    Scene scene;
    ASSERT_NO_THROW(scene = parseScene(random.yaml, "random"));  // walks clear of every wall
    EXPECT_EQ(scene.name, "random_" + std::to_string(seed));
    EXPECT_EQ(scene.seed, seed);
    EXPECT_GE(scene.duration, 40.0);
    EXPECT_LE(scene.duration, 80.0);
    EXPECT_TRUE(scene.physics.enabled);
    EXPECT_EQ(scene.lidars.size(), seed % 2 ? 1u : 2u);
    for (const LidarSpec& lidar : scene.lidars)
      EXPECT_TRUE(lidar.sweep);
    layouts.insert(random.description.description.substr(0, 5));

    const RobotTrajectory robot(scene.robot, scene.duration);
    EXPECT_GT(robot.pathLength(), 5.0);
    std::vector<Pedestrian> walkers;
    for (const PersonSpec& spec : scene.people)
      walkers.emplace_back(spec);
    for (std::size_t i = 0; i < walkers.size(); ++i) {
      for (std::size_t j = i + 1; j < walkers.size(); ++j) {
        EXPECT_FALSE(overlapAnywhere(walkers[i], walkers[j], scene.duration))
            << walkers[i].spec().name << " and " << walkers[j].spec().name;
      }
      for (double t = 0.0; t <= scene.duration; t += 0.02) {
        const auto p = walkers[i].positionAt(t);
        if (p) {
          EXPECT_GE((*p - robot.stateAt(t).pose.position()).norm(), walkers[i].spec().radius + 0.6)
              << walkers[i].spec().name << " at " << t;
        }
      }
      legged += walkers[i].spec().legs;
    }
    people += static_cast<int>(walkers.size());
    for (std::size_t s = 0; s < scene.world.segments().size(); ++s)
      glass_surfaces += scene.world.segments()[s].material == Material::kGlass;
    for (const World::ArcPrimitive& arc : scene.world.arcs())
      glass_surfaces += arc.material == Material::kGlass;
  }
  EXPECT_EQ(layouts.size(), 2u);  // corridors and halls
  EXPECT_GT(glass_surfaces, 10);
  EXPECT_GT(people, 30);
  EXPECT_GT(legged, people / 2);
  EXPECT_LT(legged, people);
}

TEST(RandomSceneTest, OptionsReachTheFile) {
  RandomSceneOptions options;
  options.seed = 5;
  options.setup = "carmen_sparse";
  options.duration = 25.0;
  options.odometry_drift = false;
  Scene scene = parseScene(generateRandomScene(options).yaml);
  EXPECT_DOUBLE_EQ(scene.duration, 25.0);
  EXPECT_TRUE(scene.odometry.enabled);  // with every error at zero: map -> odom is the identity
  EXPECT_DOUBLE_EQ(scene.odometry.xy_noise, 0.0);
  EXPECT_DOUBLE_EQ(scene.odometry.yaw_bias_deg_per_m, 0.0);
  EXPECT_DOUBLE_EQ(scene.logger.keep_every_m, 1.0);  // the setup's logger
  EXPECT_EQ(scene.lidars.front().beam_count, 361);
  ScanLoggerSpec logger;
  logger.keep_every_deg = 10.0;
  options.logger = logger;
  scene = parseScene(generateRandomScene(options).yaml);
  EXPECT_DOUBLE_EQ(scene.logger.keep_every_m, 0.0);
  EXPECT_DOUBLE_EQ(scene.logger.keep_every_deg, 10.0);
}

struct ScanRecorder : SimulationSink {
  void onRobotState(double, const RobotState&, const Pose2&) override {}
  void onScan(const SimScan& scan, const LidarSpec&) override { scans.push_back(scan); }
  std::vector<SimScan> scans;
};

// Sets every `key: value` of the scene text to `value`.
std::string withAll(std::string text, const std::string& key, const std::string& value) {
  for (std::size_t at = text.find(key + ": "); at != std::string::npos;
       at = text.find(key + ": ", at + 1)) {
    const std::size_t from = at + key.size() + 2;
    text.replace(from, text.find_first_of(",}\n", from) - from, value);
  }
  return text;
}

TEST(RandomSceneTest, TruthAgreesWithTheWorldBeamByBeam) {
  // A random scene without noise and with scans taken at one instant, so that every beam can be
  // traced again from the true pose: a direct return lies on the first surface along the beam
  // and is of its material, motion is a person in front of it, a reflection lies beyond it.
  RandomSceneOptions options;
  options.seed = 1003;
  options.duration = 6.0;
  std::string text = generateRandomScene(options).yaml;
  text = withAll(text, "sweep", "false");
  text = withAll(text, "range_noise_sigma", "0");
  text = withAll(text, "range_noise_per_m", "0");
  const Scene scene = parseScene(text);
  Simulator simulator(scene, scene.seed);
  ScanRecorder recorder;
  simulator.run(recorder);
  std::vector<Pedestrian> people;
  for (const PersonSpec& spec : scene.people)
    people.emplace_back(spec);

  std::map<int, int> checked;
  for (const SimScan& scan : recorder.scans) {
    const LidarSpec& lidar = scene.lidars[scan.lidar_index];
    const Pose2 laser = simulator.trajectory().stateAt(scan.time).pose.compose(lidar.mount());
    const std::vector<Circle> bodies = peopleAt(people, scan.time);
    for (int i = 0; i < lidar.beam_count; ++i) {
      const auto truth = static_cast<BeamClass>(scan.classes[i]);
      const double range = scan.ranges[i];
      const double angle = laser.yaw + lidar.beamAngle(i);
      const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
      const auto wall = scene.world.intersect(laser.position(), direction, 1e9, {});
      const auto first = scene.world.intersect(laser.position(), direction, 1e9, bodies);
      if (truth == BeamClass::kNoReturn) {
        EXPECT_FALSE(std::isfinite(range) && range > 0) << i;
        continue;
      }
      ASSERT_TRUE(first.has_value()) << "a return with nothing along beam " << i;
      const double tolerance = 1e-4 * std::max(1.0, range);
      ++checked[static_cast<int>(truth)];
      switch (truth) {
        case BeamClass::kMotion:
          EXPECT_TRUE(first->is_person) << i;
          EXPECT_NEAR(range, first->distance, tolerance) << i;
          break;
        case BeamClass::kReflection:
          EXPECT_GE(range, first->distance - tolerance) << i;
          break;
        default: {
          ASSERT_FALSE(first->is_person) << i;
          EXPECT_NEAR(range, wall->distance, tolerance) << i;
          const Material material = wall->material;
          const bool agrees = truth == BeamClass::kDiffuse ? material == Material::kDiffuse
                              : truth == BeamClass::kGlass
                                  ? material == Material::kGlass
                                  : material == Material::kMetal || material == Material::kMirror;
          EXPECT_TRUE(agrees) << "beam " << i << " " << beamClassName(truth) << " on "
                              << materialName(material);
        }
      }
    }
  }
  for (const BeamClass beam :
       {BeamClass::kDiffuse, BeamClass::kGlass, BeamClass::kMotion, BeamClass::kReflection}) {
    EXPECT_GT(checked[static_cast<int>(beam)], 0) << beamClassName(beam);
  }
}

TEST(SceneDescriptionTest, NumbersReadBackExactly) {
  for (const double value : {0.1, 1.0 / 3.0, -135.0, 0.3515625, 1e-7, 12345.678}) {
    EXPECT_EQ(std::stod(formatNumber(value)), value) << formatNumber(value);
  }
  EXPECT_EQ(formatNumber(-0.0), "0");
  EXPECT_EQ(formatNumber(2.5), "2.5");
}

}  // namespace
}  // namespace rfm::sim
