// From CARMEN lines to scans: beam angles, no-return readings, mounts and base poses.

#include "reflectance_field_map/tools/carmen_conversion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

namespace {

using rfm::tools::CarmenConversion;
using rfm::tools::ConversionOptions;
using rfm::tools::convertCarmenLog;
using rfm::tools::LaserLine;
using rfm::tools::oldLaserGeometry;
using rfm::tools::Pose2D;

constexpr double kDeg = M_PI / 180.0;

rfm::tools::CarmenLog logOf(const std::string& text) {
  std::istringstream in(text);
  return rfm::tools::readCarmenLog(in);
}

std::string allNotes(const CarmenConversion& c) {
  std::string text;
  for (const std::string& note : c.notes)
    text += note + "\n";
  return text;
}

std::string flaser(const std::string& name, const std::vector<double>& ranges, const Pose2D& laser,
                   const Pose2D& robot, double stamp) {
  std::ostringstream line;
  line.precision(10);
  line << name << ' ' << ranges.size();
  for (double r : ranges)
    line << ' ' << r;
  line << ' ' << laser.x << ' ' << laser.y << ' ' << laser.theta << ' ' << robot.x << ' ' << robot.y
       << ' ' << robot.theta << ' ' << stamp << " host " << stamp << '\n';
  return line.str();
}

TEST(CarmenGeometry, BeamCountsFollowCarmensConvention) {
  const std::map<std::string, std::string> none;
  for (const size_t n : {180u, 181u}) {
    const auto g = oldLaserGeometry(n, none, false, std::nullopt);
    EXPECT_NEAR(g.angle_min, -90 * kDeg, 1e-12);
    EXPECT_NEAR(g.angle_increment, 1 * kDeg, 1e-12);
    EXPECT_NE(g.origin.find("CARMEN's convention"), std::string::npos);
  }
  for (const size_t n : {360u, 361u}) {
    const auto g = oldLaserGeometry(n, none, true, std::nullopt);
    EXPECT_NEAR(g.angle_min, -90 * kDeg, 1e-12);
    EXPECT_NEAR(g.angle_increment, 0.5 * kDeg, 1e-12);
  }
  const auto g401 = oldLaserGeometry(401, none, false, std::nullopt);
  EXPECT_NEAR(g401.angle_min, -50 * kDeg, 1e-12);
  EXPECT_NEAR(g401.angle_increment, 0.25 * kDeg, 1e-12);
  // Any other count: 180 deg, as CARMEN guesses, and the note says how to change it.
  const auto g541 = oldLaserGeometry(541, none, false, std::nullopt);
  EXPECT_NEAR(g541.angle_min, -90 * kDeg, 1e-12);
  EXPECT_NEAR(g541.angle_increment, 180.0 / 540 * kDeg, 1e-12);
  EXPECT_NE(g541.origin.find("--fov"), std::string::npos) << g541.origin;
}

TEST(CarmenGeometry, FieldOfViewFromTheFlagOrTheParams) {
  const std::map<std::string, std::string> none;
  const auto flag = oldLaserGeometry(541, none, false, 270.0);
  EXPECT_NEAR(flag.angle_min, -135 * kDeg, 1e-12);
  EXPECT_NEAR(flag.angle_increment, 0.5 * kDeg, 1e-12);

  const std::map<std::string, std::string> params = {{"laser_front_laser_fov", "270"},
                                                     {"laser_front_laser_resolution", "0.5"}};
  const auto front = oldLaserGeometry(541, params, false, std::nullopt);
  EXPECT_NEAR(front.angle_min, -135 * kDeg, 1e-12);
  EXPECT_NEAR(front.angle_increment, 0.5 * kDeg, 1e-12);
  EXPECT_NE(front.origin.find("PARAM"), std::string::npos);
  // The rear laser's PARAMs are its own.
  EXPECT_NEAR(oldLaserGeometry(541, params, true, std::nullopt).angle_min, -90 * kDeg, 1e-12);
  // PARAMs that do not fit the beam count are not used, and the note says so.
  const auto misfit = oldLaserGeometry(181, params, false, std::nullopt);
  EXPECT_NEAR(misfit.angle_increment, 1 * kDeg, 1e-12);
  EXPECT_NE(misfit.origin.find("does not fit 181 beams"), std::string::npos) << misfit.origin;
}

TEST(CarmenNoReturn, TheSensorsMaxRangeCodeIsNoReturn) {
  // Intel- and campus-like readings: real returns up to 81.82 m, codes at 81.83 and 81.91 m.
  LaserLine line;
  for (int i = 0; i < 30; ++i) {
    line.ranges.insert(line.ranges.end(), {1.0, 81.0, 81.82, 81.83, 81.91});
  }
  const auto t = rfm::tools::detectNoReturnThreshold({&line});
  EXPECT_NEAR(t.threshold, 81.91 * 0.998, 1e-9);
  EXPECT_LE(t.threshold, 81.83);
  EXPECT_GT(t.threshold, 81.0);
  EXPECT_DOUBLE_EQ(t.range_max, t.threshold);
  EXPECT_NE(t.note.find("90 readings of 150"), std::string::npos) << t.note;  // 81.82-81.91

  // Orebro-like: int16 millimetre codes 32.759-32.767 m.
  LaserLine orebro;
  for (int i = 0; i < 20; ++i)
    orebro.ranges.insert(orebro.ranges.end(), {0.5, 32.63, 32.759, 32.763, 32.767});
  const auto o = rfm::tools::detectNoReturnThreshold({&orebro});
  EXPECT_GT(o.threshold, 32.63);
  EXPECT_LE(o.threshold, 32.759);
}

TEST(CarmenNoReturn, WithoutARecurringMaximumEveryReadingIsAReturn) {
  LaserLine line;
  line.ranges = {1.0, 2.0, 3.0, 7.31, 7.3, 7.29};
  const auto t = rfm::tools::detectNoReturnThreshold({&line});
  EXPECT_TRUE(std::isinf(t.threshold));
  EXPECT_GT(t.range_max, 7.31);
  EXPECT_NE(t.note.find("no max-range code"), std::string::npos) << t.note;
}

// A corrected log: both poses of each line are the corrected laser pose.
TEST(CarmenConversion, CorrectedFlaserLog) {
  std::string text = "PARAM robot_frontlaser_offset -0.04 nohost 0\n";
  std::vector<double> ranges(181, 2.0);
  ranges[0] = 81.83;
  ranges[1] = 0.0;
  for (int i = 0; i < 12; ++i) {
    const Pose2D pose{0.5 * i, 0.1 * i, 0.05 * i};
    text += flaser("FLASER", ranges, pose, pose, 100.0 + i);
    text += "ODOM 0 0 0 0 0 0 0 pippo 0\n";
  }
  const CarmenConversion c = convertCarmenLog(logOf(text), ConversionOptions());
  ASSERT_EQ(c.scans.size(), 12u);
  ASSERT_TRUE(c.front_mount);
  EXPECT_NEAR(c.front_mount->x, 0.0, 1e-12);
  EXPECT_NEAR(c.front_mount->theta, 0.0, 1e-12);
  EXPECT_FALSE(c.rear_mount);
  EXPECT_NE(allNotes(c).find("base_link is the laser's (corrected) pose"), std::string::npos)
      << allNotes(c);
  for (size_t i = 0; i < c.scans.size(); ++i) {
    const auto& scan = c.scans[i];
    EXPECT_FALSE(scan.rear);
    EXPECT_DOUBLE_EQ(scan.time, 100.0 + static_cast<double>(i));
    EXPECT_NEAR(scan.base_pose.x, 0.5 * static_cast<double>(i), 1e-9);
    EXPECT_NEAR(scan.base_pose.theta, 0.05 * static_cast<double>(i), 1e-9);
    EXPECT_NEAR(scan.angle_min, -M_PI / 2, 1e-12);
    EXPECT_NEAR(scan.angle_increment, M_PI / 180, 1e-12);
    ASSERT_EQ(scan.ranges.size(), 181u);
    EXPECT_TRUE(std::isinf(scan.ranges[0]) && scan.ranges[0] > 0);  // the max-range code
    EXPECT_TRUE(std::isnan(scan.ranges[1]));                        // 0: no measurement
    EXPECT_FLOAT_EQ(scan.ranges[2], 2.0f);
    EXPECT_LT(2.0, scan.range_max);
    EXPECT_LE(scan.range_max, 81.83);
  }
  // The ODOM lines stamped 0 after each scan take the scan's time.
  ASSERT_EQ(c.odometry.size(), 12u);
  for (size_t i = 0; i < c.odometry.size(); ++i)
    EXPECT_DOUBLE_EQ(c.odometry[i].time, c.scans[i].time);
}

// ROBOTLASER1 keeps the robot pose and the laser pose apart: a real mount.
TEST(CarmenConversion, RobotLaserMountAndGeometry) {
  std::string text;
  for (int i = 0; i < 5; ++i) {
    const double th = 0.3 * i, x = 1.0 * i, y = -0.5 * i;
    const double lx = x + 0.2 * std::cos(th), ly = y + 0.2 * std::sin(th);
    std::ostringstream line;
    line.precision(12);
    line << "ROBOTLASER1 0 -2.0 4.0 0.02 30.0 0.01 0 3 1.0 30.0 45.0 3 7 8 9 " << lx << ' ' << ly
         << ' ' << th << ' ' << x << ' ' << y << ' ' << th << " 0 0 0 0 0 " << 5.0 + i << " host "
         << 5.0 + i << '\n';
    text += line.str();
  }
  const CarmenConversion c = convertCarmenLog(logOf(text), ConversionOptions());
  ASSERT_TRUE(c.front_mount);
  EXPECT_NEAR(c.front_mount->x, 0.2, 1e-9);
  EXPECT_NEAR(c.front_mount->y, 0.0, 1e-9);
  EXPECT_NEAR(c.front_mount->theta, 0.0, 1e-9);
  ASSERT_EQ(c.scans.size(), 5u);
  EXPECT_NEAR(c.scans[3].base_pose.x, 3.0, 1e-9);  // the robot pose
  EXPECT_NEAR(c.scans[3].base_pose.y, -1.5, 1e-9);
  EXPECT_DOUBLE_EQ(c.scans[0].angle_min, -2.0);
  EXPECT_DOUBLE_EQ(c.scans[0].angle_increment, 0.02);
  EXPECT_DOUBLE_EQ(c.scans[0].range_max, 30.0);
  EXPECT_FLOAT_EQ(c.scans[0].ranges[0], 1.0f);
  EXPECT_TRUE(std::isinf(c.scans[0].ranges[1]));  // at maximum_range
  EXPECT_TRUE(std::isinf(c.scans[0].ranges[2]));
  EXPECT_EQ(c.scans[0].intensities, (std::vector<float>{7, 8, 9}));
}

// Raw odometry beside a corrected laser pose: the second pose drifts, so it is no mount.
TEST(CarmenConversion, DriftingSecondPoseIsIgnored) {
  std::string text;
  for (int i = 0; i < 6; ++i) {
    const Pose2D laser{1.0 * i, 0.0, 0.0};
    const Pose2D odometry{1.05 * i, 0.02 * i, 0.01 * i};
    text += flaser("FLASER", std::vector<double>(180, 3.0), laser, odometry, 1.0 + i);
  }
  const CarmenConversion c = convertCarmenLog(logOf(text), ConversionOptions());
  ASSERT_TRUE(c.front_mount);
  EXPECT_NEAR(c.front_mount->x, 0.0, 1e-12);
  EXPECT_NEAR(c.scans[5].base_pose.x, 5.0, 1e-9);
  EXPECT_NE(allNotes(c).find("drifts from the laser pose"), std::string::npos) << allNotes(c);
}

// A corrected log with a rear laser 0.3 m behind the front one, facing backwards: its mount is
// found against the front laser's trajectory.
TEST(CarmenConversion, RearLaserMountFromTheTrajectory) {
  std::string text;
  for (int i = 0; i < 20; ++i) {
    const double t = 10.0 + i;
    const Pose2D front{0.4 * i, 0.0, 0.0};
    text += flaser("FLASER", std::vector<double>(181, 2.0), front, front, t);
    const Pose2D rear_pose{0.4 * i + 0.2 - 0.3, 0.0, M_PI};  // half a step later
    text += flaser("RLASER", std::vector<double>(181, 2.0), rear_pose, rear_pose, t + 0.5);
  }
  const CarmenConversion c = convertCarmenLog(logOf(text), ConversionOptions());
  ASSERT_TRUE(c.rear_mount);
  EXPECT_NEAR(c.rear_mount->x, -0.3, 1e-6);
  EXPECT_NEAR(c.rear_mount->y, 0.0, 1e-6);
  EXPECT_NEAR(std::abs(c.rear_mount->theta), M_PI, 1e-6);
  size_t rear = 0;
  for (const auto& scan : c.scans) {
    if (!scan.rear) continue;
    ++rear;
    // base_link at a rear scan lies on the front trajectory.
    EXPECT_NEAR(scan.base_pose.y, 0.0, 1e-6);
    EXPECT_NEAR(scan.base_pose.theta, 0.0, 1e-6);
  }
  EXPECT_EQ(rear, 20u);
  // Scans stay in file order with increasing times.
  for (size_t i = 1; i < c.scans.size(); ++i)
    EXPECT_GT(c.scans[i].time, c.scans[i - 1].time);
}

TEST(CarmenConversion, OptionsOverride) {
  std::string text;
  for (int i = 0; i < 4; ++i) {
    const Pose2D pose{0.3 * i, 0.0, 0.0};
    text += flaser("FLASER", {1.0, 5.0, 9.0}, pose, pose, 0.0);
  }
  ConversionOptions options;
  options.max_range = 5.0;
  options.field_of_view_deg = 90.0;
  options.synthetic_period = 0.25;
  const CarmenConversion c = convertCarmenLog(logOf(text), options);
  ASSERT_EQ(c.scans.size(), 4u);
  EXPECT_NEAR(c.scans[0].angle_min, -45 * kDeg, 1e-12);
  EXPECT_NEAR(c.scans[0].angle_increment, 45 * kDeg, 1e-12);
  EXPECT_FLOAT_EQ(c.scans[0].ranges[0], 1.0f);
  EXPECT_TRUE(std::isinf(c.scans[0].ranges[1]));
  EXPECT_DOUBLE_EQ(c.scans[1].time - c.scans[0].time, 0.25);
}

// Without --period the synthetic clock runs at 0.3 m/s along the path: 0.6 m steps, 2 s.
TEST(CarmenConversion, SyntheticPeriodFromThePath) {
  std::string text;
  for (int i = 0; i < 5; ++i) {
    const Pose2D pose{0.6 * i, 0.0, 0.0};
    text += flaser("FLASER", std::vector<double>(180, 3.0), pose, pose, 0.0);
  }
  const CarmenConversion c = convertCarmenLog(logOf(text), ConversionOptions());
  EXPECT_EQ(c.clock_source, rfm::tools::ClockSource::kSynthetic);
  EXPECT_NEAR(c.scans[1].time - c.scans[0].time, 2.0, 1e-9);
  EXPECT_NE(allNotes(c).find("synthesised"), std::string::npos) << allNotes(c);
}

// With a rear laser the lines share the period: the front laser still steps 2 s, and the rear
// laser's turned pose does not count as a step.
TEST(CarmenConversion, SyntheticPeriodSharedByTwoLasers) {
  std::string text;
  for (int i = 0; i < 5; ++i) {
    const Pose2D front{0.6 * i, 0.0, 0.0};
    const Pose2D rear{0.6 * i - 0.3, 0.0, M_PI};
    text += flaser("FLASER", std::vector<double>(180, 3.0), front, front, 0.0);
    text += flaser("RLASER", std::vector<double>(180, 3.0), rear, rear, 0.0);
  }
  const CarmenConversion c = convertCarmenLog(logOf(text), ConversionOptions());
  ASSERT_EQ(c.scans.size(), 10u);
  EXPECT_NEAR(c.scans[1].time - c.scans[0].time, 1.0, 1e-9);
  EXPECT_NEAR(c.scans[2].time - c.scans[0].time, 2.0, 1e-9);
}

TEST(CarmenConversion, NoLaserLineIsAnError) {
  EXPECT_THROW(convertCarmenLog(logOf("ODOM 0 0 0 0 0 0 1 h 1\n"), ConversionOptions()),
               rfm::tools::ConversionError);
}

}  // namespace
