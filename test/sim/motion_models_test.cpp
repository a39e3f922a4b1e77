// What moves in a procedural scene and how it is recorded: legs, odometry drift, the chassis
// tilt, the thinning logger, and the sweep of a scan while the robot turns.
#include <gtest/gtest.h>

#include <cmath>

#include "reflectance_field_map/sim/chassis_tilt.h"
#include "reflectance_field_map/sim/odometry.h"
#include "reflectance_field_map/sim/people.h"
#include "reflectance_field_map/sim/scan_logger.h"
#include "reflectance_field_map/sim/scene.h"
#include "reflectance_field_map/sim/simulator.h"

namespace rfm::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

PersonSpec legged(double speed = 1.2) {
  PersonSpec spec;
  spec.legs = true;
  spec.radius = 0.4;
  spec.speed = speed;
  spec.waypoints = {{{0, 0}, 0.0}, {{10, 0}, 4.0}, {{10, 5}, 0.0}};
  return spec;
}

TEST(LegsTest, TwoLegsStayWithinTheFootprintAndAlternate) {
  const Pedestrian person(legged());
  EXPECT_LE(person.legReach(), 0.4);
  std::vector<Circle> previous;
  int still_steps = 0, steps = 0;
  for (double t = 0.0; t < 8.0; t += 0.02) {
    std::vector<Circle> legs;
    person.appendBody(t, legs);
    ASSERT_EQ(legs.size(), 2u);
    const Eigen::Vector2d centre = *person.positionAt(t);
    for (const Circle& leg : legs) {
      EXPECT_LE((leg.center - centre).norm() + leg.radius, person.spec().radius + 1e-9) << t;
      EXPECT_DOUBLE_EQ(leg.radius, 0.06);
    }
    EXPECT_GT((legs[0].center - legs[1].center).norm(), 0.1) << t;  // a hip's width apart
    if (!previous.empty() && t < 7.0) {                             // walking the first leg
      ++steps;
      // At a lidar's height a planted leg only leans with the body: it moves at a third of its
      // speed, a swinging one at more than the body's.
      const double slow = std::min((legs[0].center - previous[0].center).norm(),
                                   (legs[1].center - previous[1].center).norm());
      if (slow < 0.02 * 1.2 * 0.5) ++still_steps;
    }
    previous = legs;
  }
  // One leg is planted most of the time.
  EXPECT_GT(still_steps, steps / 2);
}

TEST(LegsTest, LegsStandStillDuringAPauseAndTheDiscStaysWithoutLegs) {
  const Pedestrian person(legged());
  std::vector<Circle> a, b;
  person.appendBody(10.0 / 1.2 + 0.5, a);  // pausing at (10, 0)
  person.appendBody(10.0 / 1.2 + 3.5, b);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_TRUE(a[0].center.isApprox(b[0].center));
  EXPECT_TRUE(a[1].center.isApprox(b[1].center));

  PersonSpec disc = legged();
  disc.legs = false;
  std::vector<Circle> body;
  Pedestrian(disc).appendBody(2.0, body);
  ASSERT_EQ(body.size(), 1u);
  EXPECT_DOUBLE_EQ(body[0].radius, 0.4);
}

TEST(LegsTest, AFootprintSmallerThanTheLegsReachIsRejected) {
  PersonSpec spec = legged(1.5);
  spec.radius = 0.25;
  EXPECT_THROW(Pedestrian{spec}, std::invalid_argument);
}

// Drives 20 m east in 1 cm steps.
Pose2 driveEast(OdometryModel& odometry, double metres) {
  Pose2 odometry_pose;
  for (int i = 1; i <= static_cast<int>(metres * 100); ++i)
    odometry_pose = odometry.advance({i * 0.01, 0.0, 0.0});
  return odometry_pose;
}

TEST(OdometryTest, WithoutDriftItIsTheTruePath) {
  OdometryModel odometry(OdometryDrift{}, {}, 1);
  const Pose2 pose = odometry.advance({3.0, 4.0, 0.5});
  EXPECT_DOUBLE_EQ(pose.x, 3.0);
  EXPECT_DOUBLE_EQ(pose.y, 4.0);
  EXPECT_DOUBLE_EQ(pose.yaw, 0.5);
}

// Drift switched on with every error at zero: each test sets the one it checks.
OdometryDrift noErrors() {
  OdometryDrift drift;
  drift.enabled = true;
  drift.xy_noise = drift.yaw_noise_deg = drift.turn_noise_deg = 0.0;
  drift.scale_error = drift.turn_scale_error = drift.yaw_bias_deg_per_m = 0.0;
  return drift;
}

TEST(OdometryTest, SystematicErrorsScaleTheDistanceAndBendTheHeading) {
  OdometryDrift drift = noErrors();
  drift.scale_error = 0.02;
  OdometryModel scaled(drift, {}, 1);
  EXPECT_NEAR(driveEast(scaled, 20.0).x, 20.4, 1e-6);

  drift.scale_error = 0.0;
  drift.yaw_bias_deg_per_m = 0.1;
  OdometryModel bent(drift, {}, 1);
  EXPECT_NEAR(driveEast(bent, 20.0).yaw, 2.0 * kDeg, 1e-9);

  drift.yaw_bias_deg_per_m = 0.0;
  drift.turn_scale_error = 0.05;
  OdometryModel turning(drift, {}, 1);
  Pose2 pose;
  for (int i = 1; i <= 90; ++i)
    pose = turning.advance({0.0, 0.0, i * kDeg});
  EXPECT_NEAR(pose.yaw, 94.5 * kDeg, 1e-9);
}

TEST(OdometryTest, RandomWalkGrowsWithTheSquareRootOfTheDistance) {
  OdometryDrift drift = noErrors();
  drift.yaw_noise_deg = 0.5;
  double sum_short = 0.0, sum_long = 0.0;
  const int runs = 200;
  for (int seed = 0; seed < runs; ++seed) {
    OdometryModel a(drift, {}, seed), b(drift, {}, seed + 1000);
    const double short_yaw = driveEast(a, 4.0).yaw, long_yaw = driveEast(b, 16.0).yaw;
    sum_short += short_yaw * short_yaw;
    sum_long += long_yaw * long_yaw;
  }
  const double sigma_short = std::sqrt(sum_short / runs) / kDeg;
  const double sigma_long = std::sqrt(sum_long / runs) / kDeg;
  EXPECT_NEAR(sigma_short, 0.5 * 2.0, 0.2);  // 0.5 deg per sqrt(m) over 4 m
  EXPECT_NEAR(sigma_long, 0.5 * 4.0, 0.4);
}

TEST(ScanLoggerTest, KeepsAScanPerDistanceOrTurnPerLidar) {
  ScanLoggerSpec spec;
  spec.keep_every_m = 1.0;
  spec.keep_every_deg = 30.0;
  ScanLogger logger(spec, 2);
  EXPECT_TRUE(logger.keep(0, {0.0, 0.0, 0.0}));  // the first
  EXPECT_FALSE(logger.keep(0, {0.9, 0.0, 0.0}));
  EXPECT_TRUE(logger.keep(1, {0.9, 0.0, 0.0}));  // the other lidar's first
  EXPECT_TRUE(logger.keep(0, {1.0, 0.0, 0.0}));
  EXPECT_FALSE(logger.keep(0, {1.5, 0.0, 29.0 * kDeg}));
  EXPECT_TRUE(logger.keep(0, {1.5, 0.0, 31.0 * kDeg}));
  ScanLogger everything(ScanLoggerSpec{}, 1);
  EXPECT_TRUE(everything.keep(0, {0.0, 0.0, 0.0}));
  EXPECT_TRUE(everything.keep(0, {0.0, 0.0, 0.0}));
  spec.keep_every_m = -1.0;
  EXPECT_THROW(ScanLogger(spec, 1), std::invalid_argument);
}

TEST(RobotPauseTest, TheRobotWaitsAtAWaypointBeforeDrivingOn) {
  const Scene scene = parseScene(R"(
name: wait
duration: 30
walls: [{type: segment, material: diffuse, points: [[0, 5], [10, 5]]}]
robot: {speed: 1.0, start_delay: 0, waypoints: [[0, 0], [4, 0, 5.0], [8, 0]]}
)");
  ASSERT_EQ(scene.robot.pauses.size(), 2u);
  const RobotTrajectory trajectory(scene.robot, scene.duration);
  EXPECT_NEAR(trajectory.stateAt(4.5).pose.x, 4.0, 1e-9);  // arrived at 4 s, waits until 9 s
  EXPECT_DOUBLE_EQ(trajectory.stateAt(8.9).linear_velocity, 0.0);
  EXPECT_NEAR(trajectory.stateAt(11.0).pose.x, 6.0, 1e-9);
  EXPECT_NEAR(trajectory.motionEndTime(), 13.0, 1e-9);
  EXPECT_THROW(parseScene(R"(
name: bad
duration: 3
walls: [{type: segment, material: diffuse, points: [[0, 5], [10, 5]]}]
robot: {waypoints: [[0, 0], [4, 0, -1]]}
)"),
               SceneError);
}

TEST(ChassisTiltTest, BumpsRockTheChassisWhileDrivingAndItSettlesWhenStanding) {
  TrajectorySpec path;
  path.waypoints = {{0, 0}, {40, 0}};
  path.speed = 1.0;
  path.start_delay = 20.0;
  const RobotTrajectory trajectory(path, 70.0);
  RealisticPhysics physics;
  physics.bump_tilt_deg = 1.0;
  physics.standing_tilt_deg = 0.05;
  const ChassisTilt tilt(physics, trajectory, 70.0, 3);
  auto spread = [&](double from, double to) {
    double sum = 0.0;
    int n = 0;
    for (double t = from; t < to; t += 0.05, ++n)
      sum += std::pow(tilt.at(t).pitch, 2);
    return std::sqrt(sum / n) / kDeg;
  };
  EXPECT_LT(spread(2.0, 19.0), 0.15);          // standing
  EXPECT_NEAR(spread(22.0, 59.0), 1.0, 0.35);  // driving at 1 m/s
}

const char* kSweepScene = R"(
name: sweep
duration: 3
physics: {bump_tilt_deg: 0, standing_tilt_deg: 0, empty_echo_probability: 0, grazing_dropout: 0,
          range_dropout: 0, gloss_probability: 0}
walls:
  - {type: polyline, material: diffuse, closed: true, points: [[-5, -5], [5, -5], [5, 5], [-5, 5]]}
robot:
  turn_rate_deg: 90
  start_delay: 0
  initial_yaw_deg: 0
  waypoints: [[0, 0], [0, 4]]
lidars:
  - {topic: /scan, frame_id: laser, mount: [0, 0, 0.3, 0], beam_count: 361, angle_min_deg: -90,
     angle_increment_deg: 0.5, rate_hz: 5, range_noise_sigma: 0, dropout_probability: 0,
     sweep: SWEEP}
)";

struct ScanSink : SimulationSink {
  void onRobotState(double, const RobotState&, const Pose2&) override {}
  void onScan(const SimScan& scan, const LidarSpec&) override { scans.push_back(scan); }
  std::vector<SimScan> scans;
};

TEST(SweepTest, ABeamTakenLaterSeesTheRoomFromWhereTheTurningRobotHasGot) {
  auto run = [](const char* sweep) {
    std::string text = kSweepScene;
    text.replace(text.find("SWEEP"), 5, sweep);
    const Scene scene = parseScene(text);
    Simulator simulator(scene, 1);
    ScanSink sink;
    simulator.run(sink);
    return sink.scans;
  };
  const std::vector<SimScan> instant = run("false"), swept = run("true");
  ASSERT_EQ(instant.size(), swept.size());
  // The first scan is taken at t = 0 while the robot turns at 90 deg/s toward (0, 4). The first
  // beam is taken at (about) the stamp either way; the last, half a turn of the mirror later
  // (0.1 s), has turned 9 deg further.
  EXPECT_NEAR(instant[0].ranges.front(), swept[0].ranges.front(), 1e-4);
  EXPECT_NE(instant[0].ranges.back(), swept[0].ranges.back());
  const double expected_last = 5.0 / std::cos(9.0 * kDeg);  // the +90 deg beam now at 99 deg
  EXPECT_NEAR(swept[0].ranges.back(), expected_last, 1e-3);
  EXPECT_NEAR(instant[0].ranges.back(), 5.0, 1e-3);
}

}  // namespace
}  // namespace rfm::sim
