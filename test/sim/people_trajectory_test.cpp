// People and robot motion over time.
#include <gtest/gtest.h>

#include <cmath>

#include "reflectance_field_map/sim/people.h"
#include "reflectance_field_map/sim/trajectory.h"

namespace rfm::sim {
namespace {

PersonSpec walker() {
  PersonSpec spec;
  spec.speed = 1.0;
  spec.start_time = 2.0;
  spec.end_time = 100.0;
  spec.waypoints = {{{0, 0}, 0.0}, {{4, 0}, 3.0}, {{4, 2}, 0.0}};
  return spec;
}

TEST(PedestrianTest, WalksPausesAndLeaves) {
  const Pedestrian person(walker());
  EXPECT_FALSE(person.positionAt(1.9).has_value());  // not yet in the scene
  EXPECT_TRUE(person.positionAt(2.0)->isApprox(Eigen::Vector2d(0, 0)));
  EXPECT_TRUE(person.positionAt(4.0)->isApprox(Eigen::Vector2d(2, 0)));
  EXPECT_TRUE(person.positionAt(6.5)->isApprox(Eigen::Vector2d(4, 0)));  // pausing 3 s
  EXPECT_TRUE(person.positionAt(8.9)->isApprox(Eigen::Vector2d(4, 0)));
  EXPECT_TRUE(person.positionAt(10.0)->isApprox(Eigen::Vector2d(4, 1)));
  EXPECT_DOUBLE_EQ(person.cycleDuration(), 9.0);
  EXPECT_FALSE(person.positionAt(11.5).has_value());  // reached the end: left
}

TEST(PedestrianTest, LoopsUntilEndTime) {
  PersonSpec spec = walker();
  spec.loop = true;
  spec.end_time = 30.0;
  const Pedestrian person(spec);
  // Loop: 4 + 3 + 2 + back sqrt(20).
  const double cycle = 9.0 + std::sqrt(20.0);
  EXPECT_NEAR(person.cycleDuration(), cycle, 1e-12);
  EXPECT_TRUE(person.positionAt(2.0 + cycle + 2.0)->isApprox(Eigen::Vector2d(2, 0)));
  EXPECT_FALSE(person.positionAt(30.5).has_value());
  EXPECT_EQ(peopleAt({person}, 3.0).size(), 1u);
  EXPECT_EQ(peopleAt({person}, 31.0).size(), 0u);
}

TEST(PedestrianTest, RejectsInvalidSpecs) {
  PersonSpec spec = walker();
  spec.waypoints.clear();
  EXPECT_THROW(Pedestrian{spec}, std::invalid_argument);
  spec = walker();
  spec.speed = 0.0;
  EXPECT_THROW(Pedestrian{spec}, std::invalid_argument);
}

TEST(RobotTrajectoryTest, WaitsTurnsInPlaceAndDrives) {
  TrajectorySpec spec;
  spec.waypoints = {{0, 0}, {4, 0}, {4, 2}};
  spec.speed = 0.8;
  spec.turn_rate = M_PI / 4;  // 90 degrees in 2 s
  spec.start_delay = 1.0;
  const RobotTrajectory trajectory(spec, 60.0);
  EXPECT_DOUBLE_EQ(trajectory.pathLength(), 6.0);

  const RobotState waiting = trajectory.stateAt(0.5);
  EXPECT_DOUBLE_EQ(waiting.pose.x, 0.0);
  EXPECT_DOUBLE_EQ(waiting.linear_velocity, 0.0);

  const RobotState driving = trajectory.stateAt(1.0 + 2.5);  // 2 m along the first leg
  EXPECT_NEAR(driving.pose.x, 2.0, 1e-12);
  EXPECT_NEAR(driving.pose.yaw, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(driving.linear_velocity, 0.8);

  const RobotState turning = trajectory.stateAt(1.0 + 5.0 + 1.0);  // halfway through the turn
  EXPECT_NEAR(turning.pose.x, 4.0, 1e-12);
  EXPECT_NEAR(turning.pose.yaw, M_PI / 4, 1e-12);
  EXPECT_DOUBLE_EQ(turning.linear_velocity, 0.0);
  EXPECT_NEAR(turning.angular_velocity, M_PI / 4, 1e-12);

  const RobotState done = trajectory.stateAt(30.0);
  EXPECT_NEAR(done.pose.x, 4.0, 1e-12);
  EXPECT_NEAR(done.pose.y, 2.0, 1e-12);
  EXPECT_NEAR(done.pose.yaw, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(done.linear_velocity, 0.0);
  EXPECT_NEAR(trajectory.motionEndTime(), 1.0 + 5.0 + 2.0 + 2.5, 1e-12);
}

TEST(RobotTrajectoryTest, PoseComposition) {
  const Pose2 robot{1.0, 2.0, M_PI / 2};
  const Pose2 laser = robot.compose({0.35, 0.0, M_PI});
  EXPECT_NEAR(laser.x, 1.0, 1e-12);
  EXPECT_NEAR(laser.y, 2.35, 1e-12);
  EXPECT_NEAR(std::cos(laser.yaw), std::cos(-M_PI / 2), 1e-12);
  EXPECT_NEAR(std::sin(laser.yaw), std::sin(-M_PI / 2), 1e-12);
}

}  // namespace
}  // namespace rfm::sim
