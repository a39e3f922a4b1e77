// The ROS conversions (src/ros/conversions.cpp) without a ROS master: LaserScan -> core scan
// (upside-down lasers, clockwise scans, REP-117 ranges), TF -> planar poses, labels back to the
// message's beam order, filtered scans, and the OccupancyGrid / OccupancyGridUpdate geometry.
#include "reflectance_field_map/ros/conversions.h"

#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <tf2/buffer_core.h>
#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace rfm::ros_glue {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

geometry_msgs::Transform makeTransform(const Eigen::Vector3d& translation,
                                       const Eigen::Quaterniond& rotation) {
  geometry_msgs::Transform transform;
  transform.translation.x = translation.x();
  transform.translation.y = translation.y();
  transform.translation.z = translation.z();
  transform.rotation.x = rotation.x();
  transform.rotation.y = rotation.y();
  transform.rotation.z = rotation.z();
  transform.rotation.w = rotation.w();
  return transform;
}

Eigen::Quaterniond yawRollPitch(double yaw, double roll, double pitch = 0.0) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

sensor_msgs::LaserScan makeMessage(float angle_min, float angle_increment,
                                   std::vector<float> ranges) {
  sensor_msgs::LaserScan msg;
  msg.header.frame_id = "laser";
  msg.angle_min = angle_min;
  msg.angle_increment = angle_increment;
  msg.angle_max = angle_min + angle_increment * static_cast<float>(ranges.size() - 1);
  msg.range_min = 0.1f;
  msg.range_max = 30.0f;
  msg.ranges = std::move(ranges);
  return msg;
}

// Where message beam k ends, from the laser's full 3D transform, projected on the plane.
Eigen::Vector2d trueEnd(const sensor_msgs::LaserScan& msg, size_t k,
                        const Eigen::Vector3d& translation, const Eigen::Quaterniond& rotation) {
  const double angle = msg.angle_min + static_cast<double>(k) * msg.angle_increment;
  const Eigen::Vector3d in_laser =
      msg.ranges[k] * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0);
  return (rotation * in_laser + translation).head<2>();
}

// Where beam i of the core scan ends, read as the core reads a scan: beam i heads
// yaw + angle_min + i * angle_increment from the sensor's position.
Eigen::Vector2d coreEnd(const rfm::LaserScan2D& scan, const rfm::Pose2D& pose, size_t i) {
  const double angle = pose.yaw + scan.angle_min + static_cast<double>(i) * scan.angle_increment;
  return pose.position + scan.ranges[i] * Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

// ---- TF -> planar poses ---------------------------------------------------------------------

TEST(Conversions, FrameIdsLoseTheirLeadingSlashes) {
  EXPECT_EQ(tf2FrameId("/odom"), "odom");
  EXPECT_EQ(tf2FrameId("//robot/laser"), "robot/laser");
  EXPECT_EQ(tf2FrameId("base_link"), "base_link");
  EXPECT_EQ(tf2FrameId("/"), "");
  EXPECT_EQ(tf2FrameId(""), "");
}

TEST(Conversions, YawOfAQuaternionNeedNotBeNormalised) {
  for (const double yaw : {0.0, 0.3, -1.2, 2.9, -3.1}) {
    const Eigen::Quaterniond q = yawRollPitch(yaw, 0.0);
    geometry_msgs::Quaternion msg;
    msg.x = 3.0 * q.x();
    msg.y = 3.0 * q.y();
    msg.z = 3.0 * q.z();
    msg.w = 3.0 * q.w();
    EXPECT_NEAR(yawFromQuaternion(msg), yaw, 1e-12) << "yaw " << yaw;
  }
}

TEST(Conversions, TransformProjectsOnThePlane) {
  const rfm::Pose2D pose = toPose2D(makeTransform({1.5, -2.0, 0.7}, yawRollPitch(0.8, 0.0)));
  EXPECT_DOUBLE_EQ(pose.position.x(), 1.5);
  EXPECT_DOUBLE_EQ(pose.position.y(), -2.0);
  EXPECT_NEAR(pose.yaw, 0.8, 1e-12);
}

TEST(Conversions, UprightLaserKeepsItsHeading) {
  const PlanarSensorPose sensor =
      toPlanarSensorPose(makeTransform({0.3, 0.1, 0.2}, yawRollPitch(-2.5, 0.0)));
  EXPECT_FALSE(sensor.upside_down);
  EXPECT_NEAR(sensor.pose.yaw, -2.5, 1e-12);
  EXPECT_DOUBLE_EQ(sensor.pose.position.x(), 0.3);
  EXPECT_DOUBLE_EQ(sensor.pose.position.y(), 0.1);
}

TEST(Conversions, LaserRolledOverIsUpsideDownAndHeadsWhereItsXAxisPoints) {
  // Rolled by pi about x, or pitched by pi about y: both point z down.
  const PlanarSensorPose rolled =
      toPlanarSensorPose(makeTransform({-0.4, 0.0, 0.2}, yawRollPitch(3.0, M_PI)));
  EXPECT_TRUE(rolled.upside_down);
  EXPECT_NEAR(rolled.pose.yaw, 3.0, 1e-9);
  const PlanarSensorPose pitched =
      toPlanarSensorPose(makeTransform({0.0, 0.0, 0.0}, yawRollPitch(0.0, 0.0, M_PI)));
  EXPECT_TRUE(pitched.upside_down);
  // Pitched over, its x axis points backwards.
  EXPECT_NEAR(std::abs(pitched.pose.yaw), M_PI, 1e-9);
}

TEST(Conversions, SlightlyTiltedLaserIsUprightWithTheHeadingOfItsXAxis) {
  const PlanarSensorPose sensor =
      toPlanarSensorPose(makeTransform({0.0, 0.0, 0.0}, yawRollPitch(1.0, 0.05, -0.04)));
  EXPECT_FALSE(sensor.upside_down);
  EXPECT_NEAR(sensor.pose.yaw, 1.0, 1e-9);
}

TEST(Conversions, ZeroQuaternionIsTakenAsNoRotation) {
  geometry_msgs::Transform transform;
  transform.translation.x = 2.0;
  const PlanarSensorPose sensor = toPlanarSensorPose(transform);  // all-zero quaternion
  EXPECT_FALSE(sensor.upside_down);
  EXPECT_EQ(sensor.pose.yaw, 0.0);
  EXPECT_EQ(sensor.pose.position.x(), 2.0);
}

// ---- LaserScan -> core scan ------------------------------------------------------------------

TEST(Conversions, UprightScanIsCopiedBeamForBeam) {
  const sensor_msgs::LaserScan msg = makeMessage(-1.0f, 0.5f, {1.0f, 2.0f, 3.0f, 4.0f, 5.0f});
  const rfm::LaserScan2D scan = toLaserScan2D(msg);
  EXPECT_EQ(scan.angle_min, msg.angle_min);
  EXPECT_EQ(scan.angle_max, msg.angle_max);
  EXPECT_EQ(scan.angle_increment, msg.angle_increment);
  EXPECT_EQ(scan.range_min, msg.range_min);
  EXPECT_EQ(scan.range_max, msg.range_max);
  EXPECT_EQ(scan.ranges, msg.ranges);
  EXPECT_EQ(scan.validate(), "");
}

// Every beam of the core scan ends where the message's beam ends in 3D, for an upright laser
// and for one mounted upside down, with counter-clockwise and clockwise messages (negative
// angle_increment), and the core scan sweeps counter-clockwise.
TEST(Conversions, CoreScanEndsWhereTheLaserBeamsEndInSpace) {
  const std::vector<float> ranges = {1.0f, 2.5f, 3.0f, 4.0f, 0.5f, 6.0f, 7.5f, 2.0f};
  const Eigen::Vector3d translation(1.0, 2.0, 0.3);
  for (const bool clockwise : {false, true}) {
    const sensor_msgs::LaserScan msg =
        clockwise ? makeMessage(-0.25f, -0.25f, ranges) : makeMessage(-2.0f, 0.25f, ranges);
    ASSERT_EQ(isClockwise(msg), clockwise);
    for (const bool mounted_upside_down : {false, true}) {
      const Eigen::Quaterniond rotation = yawRollPitch(0.7, mounted_upside_down ? M_PI : 0.0);
      const PlanarSensorPose sensor = toPlanarSensorPose(makeTransform(translation, rotation));
      ASSERT_EQ(sensor.upside_down, mounted_upside_down);
      const rfm::LaserScan2D scan = toLaserScan2D(msg, sensor.upside_down);
      EXPECT_EQ(scan.validate(), "");
      EXPECT_GT(scan.angle_increment, 0.0f);
      const size_t n = msg.ranges.size();
      ASSERT_EQ(scan.ranges.size(), n);
      const bool reversed = reversesBeamOrder(msg, sensor.upside_down);
      EXPECT_EQ(reversed, clockwise != mounted_upside_down);
      for (size_t i = 0; i < n; ++i) {
        const size_t k = reversed ? n - 1 - i : i;  // the message beam it came from
        const Eigen::Vector2d expected = trueEnd(msg, k, translation, rotation);
        const Eigen::Vector2d actual = coreEnd(scan, sensor.pose, i);
        EXPECT_NEAR((actual - expected).norm(), 0.0, 1e-5)
            << "clockwise " << clockwise << ", upside down " << mounted_upside_down << ", beam "
            << i;
      }
    }
  }
}

// A laser turning at a constant rate while it sweeps (time_increment): after
// compensateSweepFromTf each core beam ends where the message's beam ended when it was measured,
// upright or upside down, from TF's poses at the first and the last beam.
TEST(Conversions, SweptScanEndsWhereEachBeamWasMeasured) {
  const std::vector<float> ranges = {1.0f, 2.5f, 3.0f, 4.0f, 0.5f, 6.0f, 7.5f, 2.0f};
  const double start = 100.0, time_increment = 0.01, turn_rate = 2.0;  // 0.14 rad a sweep
  const Eigen::Vector3d translation(1.0, 2.0, 0.3);
  for (const bool clockwise : {false, true})
    for (const bool mounted_upside_down : {false, true}) {
      sensor_msgs::LaserScan msg =
          clockwise ? makeMessage(-0.25f, -0.25f, ranges) : makeMessage(-2.0f, 0.25f, ranges);
      msg.header.stamp = ros::Time(start);
      msg.time_increment = static_cast<float>(time_increment);
      const size_t n = msg.ranges.size();
      const ros::Time sweep_end = sweepEnd(msg);
      EXPECT_NEAR((sweep_end - msg.header.stamp).toSec(), time_increment * (n - 1), 1e-7);  // float
      const auto rotationAt = [&](double t) {
        return yawRollPitch(0.7 + turn_rate * (t - start), mounted_upside_down ? M_PI : 0.0);
      };
      tf2::BufferCore tf;
      for (const double t : {start, sweep_end.toSec()}) {
        geometry_msgs::TransformStamped stamped;
        stamped.header.stamp = ros::Time(t);
        stamped.header.frame_id = "odom";
        stamped.child_frame_id = "laser";
        stamped.transform = makeTransform(translation, rotationAt(t));
        tf.setTransform(stamped, "test");
      }
      const PlanarSensorPose sensor =
          toPlanarSensorPose(tf.lookupTransform("odom", "laser", msg.header.stamp).transform);
      rfm::TimedScan timed;
      timed.scan = toLaserScan2D(msg, sensor.upside_down);
      timed.sensor_pose = sensor.pose;
      const bool reversed = reversesBeamOrder(msg, sensor.upside_down);
      ASSERT_TRUE(
          compensateSweepFromTf(tf, "odom", "laser", msg.header.stamp, sweep_end, reversed, timed));
      EXPECT_EQ(timed.scan.validate(), "");
      for (size_t i = 0; i < n; ++i) {
        const size_t k = reversed ? n - 1 - i : i;  // the message beam it came from
        const double measured = start + time_increment * static_cast<double>(k);
        const Eigen::Vector2d expected = trueEnd(msg, k, translation, rotationAt(measured));
        const Eigen::Vector2d actual = coreEnd(timed.scan, timed.sensor_pose, i);
        EXPECT_NEAR((actual - expected).norm(), 0.0, 1e-4)
            << "clockwise " << clockwise << ", upside down " << mounted_upside_down << ", beam "
            << i;
      }
      // Without a pose at the sweep's end nothing changes.
      rfm::TimedScan later = timed;
      EXPECT_FALSE(compensateSweepFromTf(tf, "odom", "laser", msg.header.stamp,
                                         sweep_end + ros::Duration(1.0), reversed, later));
      EXPECT_EQ(later.scan.angle_increment, timed.scan.angle_increment);
    }
  // A message that gives no sweep ends at its stamp, to the nanosecond (a wall-clock stamp does
  // not survive a round trip through seconds as a double).
  sensor_msgs::LaserScan msg = makeMessage(-2.0f, 0.25f, ranges);
  msg.time_increment = 0.0f;
  msg.header.stamp = ros::Time(1700000000, 123456789);
  EXPECT_EQ(sweepEnd(msg), msg.header.stamp);
}

// Labels computed on the core scan come back in message order, for counter-clockwise and
// clockwise messages (negative angle_increment) of upright and upside-down lasers: the label at
// message beam k belongs to the core beam that ends where message beam k ends.
TEST(Conversions, LabelsComeBackInMessageOrder) {
  const std::vector<float> ranges = {1.0f, 2.0f, 3.0f, 4.0f, 5.0f};
  const Eigen::Vector3d translation(0.0, 0.0, 0.0);
  const std::vector<rfm::RayLabel> expected = {rfm::RayLabel::kKept, rfm::RayLabel::kMotion,
                                               rfm::RayLabel::kKept, rfm::RayLabel::kReflection,
                                               rfm::RayLabel::kKept};
  for (const bool clockwise : {false, true}) {
    const sensor_msgs::LaserScan msg =
        clockwise ? makeMessage(0.6f, -0.3f, ranges) : makeMessage(-0.6f, 0.3f, ranges);
    for (const bool mounted_upside_down : {false, true}) {
      const Eigen::Quaterniond rotation = yawRollPitch(0.2, mounted_upside_down ? M_PI : 0.0);
      const PlanarSensorPose sensor = toPlanarSensorPose(makeTransform(translation, rotation));
      const rfm::LaserScan2D scan = toLaserScan2D(msg, sensor.upside_down);
      ASSERT_EQ(scan.validate(), "");
      // The core beam ending at message beam 1's end MOTION, the one at beam 3's REFLECTION.
      std::vector<rfm::RayLabel> labels(scan.ranges.size(), rfm::RayLabel::kKept);
      for (size_t i = 0; i < scan.ranges.size(); ++i) {
        const Eigen::Vector2d end = coreEnd(scan, sensor.pose, i);
        if ((end - trueEnd(msg, 1, translation, rotation)).norm() < 1e-5)
          labels[i] = rfm::RayLabel::kMotion;
        if ((end - trueEnd(msg, 3, translation, rotation)).norm() < 1e-5)
          labels[i] = rfm::RayLabel::kReflection;
      }
      EXPECT_EQ(toMessageOrder(labels, reversesBeamOrder(msg, sensor.upside_down)), expected)
          << "clockwise " << clockwise << ", upside down " << mounted_upside_down;
    }
  }
}

// REP-117 readings reach the core as they are (the core decides what each means), and an
// upside-down scan moves them with their beams.
TEST(Conversions, Rep117RangesReachTheCoreUnchanged) {
  // NaN (invalid), +inf (no return), -inf (too close), above range_max, below range_min.
  const std::vector<float> ranges = {kNaN, kInf, -kInf, 45.0f, 0.05f, 2.0f};
  const sensor_msgs::LaserScan msg = makeMessage(-1.0f, 0.4f, ranges);
  for (const bool upside_down : {false, true}) {
    const rfm::LaserScan2D scan = toLaserScan2D(msg, upside_down);
    ASSERT_EQ(scan.ranges.size(), ranges.size());
    EXPECT_EQ(scan.range_min, 0.1f);
    EXPECT_EQ(scan.range_max, 30.0f);
    EXPECT_EQ(scan.validate(), "") << "special ranges are readings, not a malformed scan";
    const size_t n = ranges.size();
    for (size_t i = 0; i < n; ++i) {
      const float from_message = ranges[upside_down ? n - 1 - i : i];
      if (std::isnan(from_message)) {
        EXPECT_TRUE(std::isnan(scan.ranges[i])) << "beam " << i;
      } else {
        EXPECT_EQ(scan.ranges[i], from_message) << "beam " << i;
      }
    }
  }
}

// A clockwise message whose ranges do not fit its angles (two beams short) stays malformed once
// turned round: validation names the count.
TEST(Conversions, ClockwiseScanWithTooFewRangesFailsValidation) {
  sensor_msgs::LaserScan msg = makeMessage(1.0f, -0.5f, {1.0f, 2.0f, 3.0f, 4.0f, 5.0f});
  msg.ranges.resize(3);
  const std::string problem = toLaserScan2D(msg).validate();
  EXPECT_NE(problem.find("3 ranges"), std::string::npos) << problem;
}

// ---- Labels and filtered scans ---------------------------------------------------------------

TEST(Conversions, LabelMessageValuesAreTheMessageConstants) {
  EXPECT_EQ(static_cast<uint8_t>(rfm::RayLabel::kNoReturn),
            reflectance_field_map::RayLabels::NO_RETURN);
  EXPECT_EQ(static_cast<uint8_t>(rfm::RayLabel::kKept), reflectance_field_map::RayLabels::KEPT);
  EXPECT_EQ(static_cast<uint8_t>(rfm::RayLabel::kMotion), reflectance_field_map::RayLabels::MOTION);
  EXPECT_EQ(static_cast<uint8_t>(rfm::RayLabel::kReflection),
            reflectance_field_map::RayLabels::REFLECTION);
  std_msgs::Header header;
  header.frame_id = "laser";
  header.stamp = ros::Time(12, 5);
  header.seq = 7;
  const reflectance_field_map::RayLabels msg =
      toRayLabelsMsg(header, "/scan_front",
                     {rfm::RayLabel::kReflection, rfm::RayLabel::kNoReturn, rfm::RayLabel::kKept,
                      rfm::RayLabel::kMotion});
  EXPECT_EQ(msg.header.frame_id, "laser");
  EXPECT_EQ(msg.header.stamp, ros::Time(12, 5));
  EXPECT_EQ(msg.header.seq, 7u);
  EXPECT_EQ(msg.scan_topic, "/scan_front");
  EXPECT_EQ(msg.labels, (std::vector<uint8_t>{3, 0, 1, 2}));
}

TEST(Conversions, FilteredScanTurnsMotionAndReflectionIntoNoReturn) {
  sensor_msgs::LaserScan msg = makeMessage(-1.0f, 0.4f, {1.0f, 2.0f, kNaN, 4.0f, 5.0f, 6.0f});
  msg.intensities = {10.0f, 20.0f, 30.0f, 40.0f, 50.0f, 60.0f};
  msg.header.seq = 3;
  // Fewer labels than beams: the last beam has none and stays as it is.
  const std::vector<rfm::RayLabel> labels = {rfm::RayLabel::kKept, rfm::RayLabel::kMotion,
                                             rfm::RayLabel::kNoReturn, rfm::RayLabel::kReflection,
                                             rfm::RayLabel::kKept};
  const sensor_msgs::LaserScan out = filterScan(msg, labels);
  EXPECT_EQ(out.header.seq, 3u);
  EXPECT_EQ(out.angle_min, msg.angle_min);
  EXPECT_EQ(out.angle_increment, msg.angle_increment);
  ASSERT_EQ(out.ranges.size(), 6u);
  EXPECT_EQ(out.ranges[0], 1.0f);
  EXPECT_EQ(out.ranges[1], kInf);  // REP-117: no return
  EXPECT_TRUE(std::isnan(out.ranges[2]));
  EXPECT_EQ(out.ranges[3], kInf);
  EXPECT_EQ(out.ranges[4], 5.0f);
  EXPECT_EQ(out.ranges[5], 6.0f);
  EXPECT_EQ(out.intensities, (std::vector<float>{10.0f, 0.0f, 30.0f, 0.0f, 50.0f, 60.0f}));
}

// ---- OccupancyGrid and OccupancyGridUpdate ---------------------------------------------------

// A map whose cells say where they are: x in [-3, 4), y in [-2, 3), every class present.
rfm::GlobalMap2D makeMap() {
  rfm::GlobalMap2D map(4);
  const rfm::CellClass classes[] = {rfm::CellClass::kFree,   rfm::CellClass::kStatic,
                                    rfm::CellClass::kGlass,  rfm::CellClass::kMetal,
                                    rfm::CellClass::kMotion, rfm::CellClass::kOccupied};
  int n = 0;
  for (int y = -2; y < 3; ++y) {
    for (int x = -3; x < 4; ++x, ++n) {
      if (n % 7 == 3) continue;  // left unknown
      map.set({x, y}, classes[n % 6]);
    }
  }
  return map;
}

int8_t expectedValue(rfm::CellClass c) {
  switch (c) {
    case rfm::CellClass::kUnknown:
      return -1;
    case rfm::CellClass::kFree:
    case rfm::CellClass::kMotion:
      return 0;
    default:
      return 100;  // static, glass, metal, occupied
  }
}

TEST(Conversions, OccupancyGridCoversTheBoxRowByRow) {
  const rfm::GlobalMap2D map = makeMap();
  const rfm::CellBox box{{-4, -2}, {3, 4}};  // one column and a row beyond the map: unknown
  const double resolution = 0.05;
  const nav_msgs::OccupancyGrid grid =
      toOccupancyGrid(map, box, resolution, "odom", ros::Time(40, 0));
  EXPECT_EQ(grid.header.frame_id, "odom");
  EXPECT_EQ(grid.header.stamp, ros::Time(40, 0));
  EXPECT_EQ(grid.info.map_load_time, ros::Time(40, 0));
  EXPECT_FLOAT_EQ(grid.info.resolution, 0.05f);
  EXPECT_EQ(grid.info.width, 7u);
  EXPECT_EQ(grid.info.height, 6u);
  // The origin is the lower-left corner of the box's first cell, not its centre.
  EXPECT_DOUBLE_EQ(grid.info.origin.position.x, -4 * resolution);
  EXPECT_DOUBLE_EQ(grid.info.origin.position.y, -2 * resolution);
  EXPECT_EQ(grid.info.origin.position.z, 0.0);
  EXPECT_EQ(grid.info.origin.orientation.w, 1.0);
  EXPECT_EQ(grid.info.origin.orientation.z, 0.0);
  ASSERT_EQ(grid.data.size(), 42u);
  std::vector<int> seen(256, 0);
  for (int row = 0; row < 6; ++row) {
    for (int col = 0; col < 7; ++col) {
      const rfm::CellIndex cell(box.min.x() + col, box.min.y() + row);
      const int8_t value = grid.data[row * 7 + col];
      EXPECT_EQ(value, expectedValue(map.get(cell))) << "cell " << cell.transpose();
      ++seen[static_cast<uint8_t>(value)];
    }
  }
  EXPECT_GT(seen[static_cast<uint8_t>(-1)], 0);
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[100], 0);
  EXPECT_EQ(seen[static_cast<uint8_t>(-1)] + seen[0] + seen[100], 42) << "only -1, 0 and 100";
}

TEST(Conversions, EmptyBoxGivesAnEmptyGrid) {
  const nav_msgs::OccupancyGrid grid =
      toOccupancyGrid(makeMap(), rfm::CellBox{{2, 2}, {2, 5}}, 0.1, "map", ros::Time(1, 0));
  EXPECT_EQ(grid.info.width, 0u);
  EXPECT_EQ(grid.info.height, 0u);
  EXPECT_TRUE(grid.data.empty());
  EXPECT_EQ(grid.header.frame_id, "map");
}

// Applying an update to the grid it refers to gives the grid of the map after the change:
// the window is clipped to the published grid and its offsets count from the grid's corner.
TEST(Conversions, UpdateWindowPatchesThePublishedGrid) {
  rfm::GlobalMap2D map = makeMap();
  const rfm::CellBox grid_box{{-3, -2}, {4, 3}};
  const double resolution = 0.05;
  nav_msgs::OccupancyGrid grid = toOccupancyGrid(map, grid_box, resolution, "odom", ros::Time());
  // Change cells, some of them outside the published grid.
  const rfm::CellBox window{{1, -4}, {6, 1}};
  for (int y = window.min.y(); y < window.max.y(); ++y) {
    for (int x = window.min.x(); x < window.max.x(); ++x)
      map.set({x, y}, (x + y) % 2 == 0 ? rfm::CellClass::kGlass : rfm::CellClass::kMotion);
  }
  const map_msgs::OccupancyGridUpdate update =
      toOccupancyGridUpdate(map, window, grid_box, "odom", ros::Time(5, 0));
  EXPECT_EQ(update.header.frame_id, "odom");
  EXPECT_EQ(update.header.stamp, ros::Time(5, 0));
  EXPECT_EQ(update.x, 4);  // cell x 1 is column 4 of a grid starting at -3
  EXPECT_EQ(update.y, 0);  // rows below the grid are cut off
  EXPECT_EQ(update.width, 3u);
  EXPECT_EQ(update.height, 3u);
  ASSERT_EQ(update.data.size(), 9u);
  for (uint32_t row = 0; row < update.height; ++row) {
    for (uint32_t col = 0; col < update.width; ++col) {
      grid.data[(update.y + row) * grid.info.width + update.x + col] =
          update.data[row * update.width + col];
    }
  }
  const nav_msgs::OccupancyGrid fresh =
      toOccupancyGrid(map, grid_box, resolution, "odom", ros::Time());
  EXPECT_EQ(grid.data, fresh.data);
}

TEST(Conversions, UpdateOutsideThePublishedGridIsEmpty) {
  const map_msgs::OccupancyGridUpdate update =
      toOccupancyGridUpdate(makeMap(), rfm::CellBox{{10, 10}, {12, 12}},
                            rfm::CellBox{{-3, -2}, {4, 3}}, "odom", ros::Time(5, 0));
  EXPECT_EQ(update.width, 0u);
  EXPECT_EQ(update.height, 0u);
  EXPECT_TRUE(update.data.empty());
  EXPECT_EQ(update.header.frame_id, "odom");
}

// ---- Markers -----------------------------------------------------------------------------

TEST(Conversions, CubeListHasACubeAtTheCentreOfEachCellOfTheClass) {
  rfm::GlobalMap2D map;
  map.set({-2, 3}, rfm::CellClass::kGlass);
  map.set({1, 0}, rfm::CellClass::kGlass);
  map.set({0, 0}, rfm::CellClass::kMetal);
  const rfm::CellBox box{{-3, -1}, {3, 4}};
  const visualization_msgs::Marker glass =
      toCubeList(map, box, rfm::CellClass::kGlass, 0.1, "odom", ros::Time(2, 0), "glass", 4);
  EXPECT_EQ(glass.type, visualization_msgs::Marker::CUBE_LIST);
  EXPECT_EQ(glass.action, visualization_msgs::Marker::ADD);
  EXPECT_EQ(glass.ns, "glass");
  EXPECT_EQ(glass.id, 4);
  EXPECT_DOUBLE_EQ(glass.scale.x, 0.1);
  ASSERT_EQ(glass.points.size(), 2u);
  EXPECT_NEAR(glass.points[0].x, 0.15, 1e-12);  // cell (1, 0): row 0 comes first
  EXPECT_NEAR(glass.points[0].y, 0.05, 1e-12);
  EXPECT_NEAR(glass.points[1].x, -0.15, 1e-12);  // cell (-2, 3)
  EXPECT_NEAR(glass.points[1].y, 0.35, 1e-12);
  EXPECT_GT(glass.color.b, glass.color.r);  // glass is blue

  const visualization_msgs::Marker motion =
      toCubeList(map, box, rfm::CellClass::kMotion, 0.1, "odom", ros::Time(2, 0), "motion", 5);
  EXPECT_TRUE(motion.points.empty());
  EXPECT_EQ(motion.action, visualization_msgs::Marker::DELETE);
}

}  // namespace
}  // namespace rfm::ros_glue
