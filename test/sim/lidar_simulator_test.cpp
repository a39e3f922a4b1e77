// Sensor model and whole-run behaviour: beam layout, REP-117 encoding, determinism per seed.
#include <gtest/gtest.h>

#include <cmath>

#include "reflectance_field_map/sim/lidar.h"
#include "reflectance_field_map/sim/scene.h"
#include "reflectance_field_map/sim/simulator.h"

namespace rfm::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(LidarTest, DefaultIsUtm30lxWith1081BeamsOver270Degrees) {
  const std::vector<LidarSpec> lidars = defaultWheelchairLidars();
  ASSERT_EQ(lidars.size(), 2u);
  for (const LidarSpec& lidar : lidars) {
    EXPECT_EQ(lidar.beam_count, 1081);
    EXPECT_NEAR(lidar.angle_min, -135.0 * kDeg, 1e-12);
    EXPECT_NEAR(lidar.angle_increment, 0.25 * kDeg, 1e-12);
    EXPECT_NEAR(lidar.angleMax(), 135.0 * kDeg, 1e-9);
    EXPECT_DOUBLE_EQ(lidar.rate_hz, 40.0);
    EXPECT_DOUBLE_EQ(lidar.range_min, 0.1);
    EXPECT_DOUBLE_EQ(lidar.range_max, 30.0);
  }
  EXPECT_EQ(lidars[0].frame_id, "laser_front");
  EXPECT_EQ(lidars[1].frame_id, "laser_rear");
  EXPECT_DOUBLE_EQ(lidars[0].mount_x, 0.35);
  EXPECT_DOUBLE_EQ(lidars[1].mount_x, -0.35);
  EXPECT_DOUBLE_EQ(lidars[1].mount_yaw, M_PI);
  EXPECT_DOUBLE_EQ(lidars[1].time_offset, 0.0125);  // half a period after the front laser
}

// Box room 10 m x 10 m centred on the robot; no noise or dropouts.
class LidarGeometryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    world_.addSegment({-5, -5}, {5, -5}, Material::kDiffuse);
    world_.addSegment({5, -5}, {5, 5}, Material::kDiffuse);
    world_.addSegment({5, 5}, {-5, 5}, Material::kDiffuse);
    world_.addSegment({-5, 5}, {-5, -5}, Material::kDiffuse);
  }
  SimScan scan(LidarSpec spec, const Pose2& robot) {
    spec.range_noise_sigma = 0.0;
    spec.dropout_probability = 0.0;
    BeamTracer tracer(world_, MaterialModel{});
    std::mt19937 rng(1);
    return LidarSensor(spec).scan(tracer, robot, 0.0, {}, 3.0 * kDeg, rng);
  }
  World world_;
};

TEST_F(LidarGeometryTest, BeamAnglesFollowMountAndRobotPose) {
  const std::vector<LidarSpec> lidars = defaultWheelchairLidars();
  const SimScan front = scan(lidars[0], {0, 0, 0});
  ASSERT_EQ(front.ranges.size(), 1081u);
  ASSERT_EQ(front.classes.size(), 1081u);
  EXPECT_NEAR(front.ranges[540], 5.0 - 0.35, 1e-5);          // straight ahead: +x wall
  EXPECT_NEAR(front.ranges[900], 5.0, 1e-5);                 // +90 degrees: +y wall
  EXPECT_NEAR(front.ranges[180], 5.0, 1e-5);                 // -90 degrees
  EXPECT_NEAR(front.ranges[0], 5.0 * std::sqrt(2.0), 1e-4);  // -135 degrees: the y = -5 wall
  const SimScan rear = scan(lidars[1], {0, 0, 0});
  EXPECT_NEAR(rear.ranges[540], 5.0 - 0.35, 1e-5);  // rear laser looks along -x
  // Robot turned by 90 degrees and moved: front laser at (1, 0.35) looking +y.
  const SimScan turned = scan(lidars[0], {1, 0, M_PI / 2});
  EXPECT_NEAR(turned.ranges[540], 5.0 - 0.35, 1e-5);
  EXPECT_NEAR(turned.ranges[180], 4.0, 1e-5);  // -90 from +y is +x: wall at x = 5 from x = 1
  for (const std::uint8_t beam_class : front.classes) {
    EXPECT_EQ(beam_class, static_cast<std::uint8_t>(BeamClass::kDiffuse));
  }
}

TEST_F(LidarGeometryTest, MissingEchoesAreReportedAsPositiveInfinity) {
  World empty;
  world_ = empty;
  world_.addSegment({2, -1}, {2, 1}, Material::kDiffuse);  // only a small piece ahead
  const SimScan result = scan(defaultWheelchairLidars()[0], {0, 0, 0});
  int infinite = 0;
  for (std::size_t i = 0; i < result.ranges.size(); ++i) {
    if (result.classes[i] == static_cast<std::uint8_t>(BeamClass::kNoReturn)) {
      EXPECT_TRUE(std::isinf(result.ranges[i]) && result.ranges[i] > 0) << i;
      ++infinite;
    } else {
      EXPECT_TRUE(std::isfinite(result.ranges[i]));
    }
  }
  EXPECT_GT(infinite, 800);  // the piece subtends about 62 of the 270 degrees
  EXPECT_EQ(result.classes[540], static_cast<std::uint8_t>(BeamClass::kDiffuse));
}

TEST_F(LidarGeometryTest, DropoutsAndNoiseAreApplied) {
  LidarSpec spec = defaultWheelchairLidars()[0];
  BeamTracer tracer(world_, MaterialModel{});
  std::mt19937 rng(3);
  spec.dropout_probability = 0.2;
  spec.range_noise_sigma = 0.012;
  const SimScan noisy = LidarSensor(spec).scan(tracer, {0, 0, 0}, 0.0, {}, 0.05, rng);
  const SimScan exact = scan(spec, {0, 0, 0});
  int dropped = 0;
  double squared_error = 0.0;
  int compared = 0;
  for (std::size_t i = 0; i < noisy.ranges.size(); ++i) {
    if (std::isinf(noisy.ranges[i])) {
      ++dropped;
      EXPECT_EQ(noisy.classes[i], 0);
      continue;
    }
    squared_error += std::pow(noisy.ranges[i] - exact.ranges[i], 2);
    ++compared;
  }
  EXPECT_NEAR(dropped / 1081.0, 0.2, 0.05);
  EXPECT_NEAR(std::sqrt(squared_error / compared), 0.012, 0.003);
}

// A small scene with glass and a person, collected in memory.
const char* kSmallScene = R"(
name: small
duration: 1.0
walls:
  - {type: polyline, material: diffuse, closed: true, points: [[-6, -6], [6, -6], [6, 6], [-6, 6]]}
  - {type: segment, material: glass, points: [[2, -3], [2, 3]]}
people:
  - {speed: 1.0, waypoints: [[0, -2], [0, 2]]}
robot:
  waypoints: [[-3, 0], [1, 0]]
)";

struct CollectingSink : SimulationSink {
  void onRobotState(double time, const RobotState& state, const Pose2&) override {
    state_times.push_back(time);
    states.push_back(state);
  }
  void onScan(const SimScan& scan, const LidarSpec&) override { scans.push_back(scan); }
  std::vector<double> state_times;
  std::vector<RobotState> states;
  std::vector<SimScan> scans;
};

CollectingSink runScene(const Scene& scene, std::uint32_t seed) {
  Simulator simulator(scene, seed);
  CollectingSink sink;
  simulator.run(sink);
  return sink;
}

TEST(SimulatorTest, SameSeedGivesIdenticalOutputDifferentSeedDifferentNoise) {
  const Scene scene = parseScene(kSmallScene);
  const CollectingSink a = runScene(scene, 7);
  const CollectingSink b = runScene(scene, 7);
  const CollectingSink c = runScene(scene, 8);
  ASSERT_EQ(a.scans.size(), b.scans.size());
  ASSERT_EQ(a.scans.size(), c.scans.size());
  std::size_t differing = 0, total = 0;
  for (std::size_t s = 0; s < a.scans.size(); ++s) {
    EXPECT_EQ(a.scans[s].ranges, b.scans[s].ranges);
    EXPECT_EQ(a.scans[s].classes, b.scans[s].classes);
    for (std::size_t i = 0; i < a.scans[s].ranges.size(); ++i) {
      ++total;
      if (a.scans[s].ranges[i] != c.scans[s].ranges[i]) ++differing;
    }
  }
  EXPECT_GT(differing, total / 2);  // noise differs on most beams
}

TEST(SimulatorTest, EmitsScansAndStatesInTimeOrderAtConfiguredRates) {
  const Scene scene = parseScene(kSmallScene);
  const CollectingSink sink = runScene(scene, 1);
  // 40 Hz per laser over [0, 1] s: front at 0, 0.025, ..., 1.0 (41), rear offset by 12.5 ms (40).
  EXPECT_EQ(sink.scans.size(), 81u);
  EXPECT_GE(sink.states.size(), 101u);
  for (std::size_t i = 1; i < sink.scans.size(); ++i) {
    EXPECT_LT(sink.scans[i - 1].time, sink.scans[i].time);
  }
  EXPECT_EQ(sink.scans[0].lidar_index, 0u);
  EXPECT_EQ(sink.scans[1].lidar_index, 1u);
  EXPECT_NEAR(sink.scans[1].time - sink.scans[0].time, 0.0125, 1e-12);
  EXPECT_GE(sink.state_times.back(), sink.scans.back().time);  // TF covers the last scan
}

TEST(SimulatorTest, SceneProducesEveryExpectedClass) {
  const Scene scene = parseScene(kSmallScene);
  Simulator simulator(scene, 1);
  CollectingSink sink;
  const SimulationSummary summary = simulator.run(sink);
  EXPECT_GT(summary.beams_per_class[static_cast<int>(BeamClass::kDiffuse)], 0u);
  EXPECT_GT(summary.beams_per_class[static_cast<int>(BeamClass::kGlass)], 0u);
  EXPECT_GT(summary.beams_per_class[static_cast<int>(BeamClass::kMotion)], 0u);
  EXPECT_GT(summary.beams_per_class[static_cast<int>(BeamClass::kReflection)], 0u);
  EXPECT_GT(summary.beams_per_class[static_cast<int>(BeamClass::kNoReturn)], 0u);  // dropouts
  EXPECT_EQ(summary.beams_per_class[static_cast<int>(BeamClass::kMetal)], 0u);
}

}  // namespace
}  // namespace rfm::sim
