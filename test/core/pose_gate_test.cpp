// PoseGate: a position farther from the last accepted one than the speed limit allows is
// refused; the allowance grows with time, so a robot that really was moved is followed again.
#include "reflectance_field_map/core/pose_gate.h"

#include <gtest/gtest.h>

#include <limits>

namespace rfm {
namespace {

TEST(PoseGate, AcceptsDrivingAndRefusesAOneKilometreGlitch) {
  PoseGate gate(5.0, 0.5);
  double t = 100.0;
  for (int i = 0; i < 40; ++i, t += 0.025)
    ASSERT_TRUE(gate.accept(t, {0.05 * i, 0.0})) << i;  // 2 m/s
  const Eigen::Vector2d last(0.05 * 39, 0.0);
  for (int i = 0; i < 40; ++i, t += 0.025)  // a second of glitch, 1 km away
    EXPECT_FALSE(gate.accept(t, last + Eigen::Vector2d(1000.0, 0.0))) << i;
  EXPECT_NEAR(gate.lastRejectedJump(), 1000.0, 1e-9);
  EXPECT_TRUE(gate.accept(t, last + Eigen::Vector2d(0.1, 0.0)));  // back where it was
}

TEST(PoseGate, FollowsARobotThatReallyMovedOnceItCouldHaveGotThere) {
  PoseGate gate(5.0, 0.5);
  ASSERT_TRUE(gate.accept(0.0, {0.0, 0.0}));
  EXPECT_FALSE(gate.accept(1.0, {20.0, 0.0}));  // 20 m in 1 s
  EXPECT_FALSE(gate.accept(3.0, {20.0, 0.0}));  // allowance 15.5 m
  EXPECT_TRUE(gate.accept(4.0, {20.0, 0.0}));   // allowance 20.5 m
  EXPECT_TRUE(gate.accept(4.01, {20.0, 0.0}));
}

TEST(PoseGate, TakesInterleavedStampsAndSlackButNoNonFinitePosition) {
  PoseGate gate(1.0, 0.5);
  ASSERT_TRUE(gate.accept(10.0, {0.0, 0.0}));
  EXPECT_TRUE(gate.accept(9.99, {0.4, 0.0}));  // a second lidar's earlier scan, within slack
  EXPECT_FALSE(gate.accept(10.0, {std::numeric_limits<double>::quiet_NaN(), 0.0}));
  EXPECT_FALSE(gate.accept(10.0, {std::numeric_limits<double>::infinity(), 0.0}));
  gate.reset();
  EXPECT_TRUE(gate.accept(0.0, {500.0, 500.0}));  // the first after a reset starts afresh
}

}  // namespace
}  // namespace rfm
