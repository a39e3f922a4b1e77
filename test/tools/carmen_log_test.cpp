// The CARMEN line reader: each message's fields, and every count checked before it is used.

#include "reflectance_field_map/tools/carmen_log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

namespace {

using rfm::tools::LaserLine;
using rfm::tools::LaserMessage;
using rfm::tools::LineError;
using rfm::tools::OdometryLine;
using rfm::tools::ParamLine;
using rfm::tools::parseCarmenLine;
using rfm::tools::SkippedLine;

std::string ranges(int n, const std::string& value = "1.5") {
  std::string text;
  for (int i = 0; i < n; ++i)
    text += " " + value;
  return text;
}

LaserLine laserOf(const std::string& line) {
  const auto parsed = parseCarmenLine(line);
  if (const auto* error = std::get_if<LineError>(&parsed)) {
    ADD_FAILURE() << error->reason;
    return {};
  }
  const auto* laser = std::get_if<LaserLine>(&parsed);
  EXPECT_NE(laser, nullptr) << line;
  return laser ? *laser : LaserLine{};
}

std::string errorOf(const std::string& line) {
  const auto parsed = parseCarmenLine(line);
  const auto* error = std::get_if<LineError>(&parsed);
  EXPECT_NE(error, nullptr) << "accepted: " << line.substr(0, 80);
  return error ? error->reason : "";
}

TEST(CarmenLine, FlaserFieldsInOrder) {
  const LaserLine laser =
      laserOf("FLASER 3 1.0 2.5 81.83 0.5 -0.25 1.57 0.4 -0.2 1.5 1071078718.5 merci 12.25");
  EXPECT_EQ(laser.message, LaserMessage::kFlaser);
  ASSERT_EQ(laser.ranges.size(), 3u);
  EXPECT_DOUBLE_EQ(laser.ranges[1], 2.5);
  EXPECT_DOUBLE_EQ(laser.ranges[2], 81.83);
  EXPECT_DOUBLE_EQ(laser.laser_pose.x, 0.5);
  EXPECT_DOUBLE_EQ(laser.laser_pose.y, -0.25);
  EXPECT_DOUBLE_EQ(laser.laser_pose.theta, 1.57);
  EXPECT_DOUBLE_EQ(laser.robot_pose.x, 0.4);
  EXPECT_DOUBLE_EQ(laser.robot_pose.theta, 1.5);
  EXPECT_DOUBLE_EQ(laser.ipc_timestamp, 1071078718.5);
  EXPECT_DOUBLE_EQ(laser.logger_timestamp, 12.25);
  EXPECT_FALSE(laser.geometry);
}

TEST(CarmenLine, RealBeamCountsAndRlaser) {
  for (const int n : {180, 181, 360, 361}) {
    const LaserLine laser =
        laserOf("FLASER " + std::to_string(n) + ranges(n) + " 0 0 0 0 0 0 1.0 pippo 1.0");
    EXPECT_EQ(laser.ranges.size(), static_cast<size_t>(n));
  }
  EXPECT_EQ(laserOf("RLASER 2 1 2 0 0 3.1 0 0 0 5 host 5").message, LaserMessage::kRlaser);
}

TEST(CarmenLine, LoggerStampIsOptional) {
  const LaserLine laser = laserOf("FLASER 2 1 2 0 0 0 0 0 0 7.5 host");
  EXPECT_DOUBLE_EQ(laser.logger_timestamp, 7.5);
  const auto odom = parseCarmenLine("ODOM 1 2 0.5 0.1 0.2 0 3.25 host");
  ASSERT_TRUE(std::holds_alternative<OdometryLine>(odom));
  EXPECT_DOUBLE_EQ(std::get<OdometryLine>(odom).logger_timestamp, 3.25);
}

TEST(CarmenLine, CountsAreCheckedAgainstTheLine) {
  // More readings claimed than the line holds (with its 8 trailing fields).
  std::string reason = errorOf("FLASER 5 1 2 3 0 0 0 0 0 0 1.0 pippo 1.0");
  EXPECT_NE(reason.find("num_readings is 5 but the 12 fields after it leave room for 4"),
            std::string::npos)
      << reason;
  // A count far beyond memory: refused before anything is reserved.
  reason = errorOf("FLASER 18446744073709551615 1 2 0 0 0 0 0 0 1 h 1");
  EXPECT_NE(reason.find("num_readings"), std::string::npos) << reason;
  reason = errorOf("FLASER 99999999999999999999999 1 2 0 0 0 0 0 0 1 h 1");
  EXPECT_NE(reason.find("not a count"), std::string::npos) << reason;
  reason = errorOf("FLASER -3 1 2 3 0 0 0 0 0 0 1 h 1");
  EXPECT_NE(reason.find("not a count"), std::string::npos) << reason;
  reason = errorOf("FLASER 2.5 1 2 0 0 0 0 0 0 1 h 1");
  EXPECT_NE(reason.find("not a count"), std::string::npos) << reason;
  reason = errorOf("FLASER 0 0 0 0 0 0 0 1 h 1");
  EXPECT_NE(reason.find("num_readings is 0"), std::string::npos) << reason;
  // Fewer readings claimed than written: fields are left over.
  reason = errorOf("FLASER 1 5 0 0 0 0 0 0 1 h 1 9");
  EXPECT_NE(reason.find("1 fields after logger_timestamp"), std::string::npos) << reason;
  reason = errorOf("FLASER");
  EXPECT_NE(reason.find("ends before"), std::string::npos) << reason;
}

TEST(CarmenLine, BadNumbersNameTheirField) {
  std::string reason = errorOf("FLASER 2 1 abc 0 0 0 0 0 0 1 h 1");
  EXPECT_NE(reason.find("range 'abc'"), std::string::npos) << reason;
  reason = errorOf("FLASER 2 1 2 nan 0 0 0 0 0 1 h 1");
  EXPECT_NE(reason.find("laser pose is not finite"), std::string::npos) << reason;
  reason = errorOf("ODOM 1 2 x 0 0 0 1 h 1");
  EXPECT_NE(reason.find("ODOM: pose 'x'"), std::string::npos) << reason;
  reason = errorOf("ODOM 1 2 3");
  EXPECT_NE(reason.find("ends before"), std::string::npos) << reason;
}

// Ranges and stamps may hold anything a logger wrote: kept for the conversion to judge.
TEST(CarmenLine, OddValuesAreKept) {
  const LaserLine laser = laserOf("FLASER 3 nan -1 1e400 0 0 0 0 0 0 1e-400 h 3.44361e-86");
  EXPECT_TRUE(std::isnan(laser.ranges[0]));
  EXPECT_DOUBLE_EQ(laser.ranges[1], -1.0);
  EXPECT_TRUE(std::isinf(laser.ranges[2]));
  EXPECT_EQ(laser.ipc_timestamp, 0.0);
  EXPECT_DOUBLE_EQ(laser.logger_timestamp, 3.44361e-86);
}

TEST(CarmenLine, RobotLaserCarriesGeometryAndRemissions) {
  const LaserLine laser = laserOf(
      "ROBOTLASER1 0 -1.5708 3.14159 0.0174533 81.9 0.01 0 3 1.0 2.0 3.0 3 10 20 30 "
      "1.2 0.0 0.1 1.0 0.0 0.1 0.3 0.05 0.55 0.1 0.2 99.5 host 99.6");
  EXPECT_EQ(laser.message, LaserMessage::kRobotLaser1);
  ASSERT_TRUE(laser.geometry);
  EXPECT_DOUBLE_EQ(laser.geometry->start_angle, -1.5708);
  EXPECT_DOUBLE_EQ(laser.geometry->angular_resolution, 0.0174533);
  EXPECT_DOUBLE_EQ(laser.geometry->maximum_range, 81.9);
  ASSERT_EQ(laser.ranges.size(), 3u);
  ASSERT_EQ(laser.remissions.size(), 3u);
  EXPECT_DOUBLE_EQ(laser.remissions[2], 30.0);
  EXPECT_DOUBLE_EQ(laser.laser_pose.x, 1.2);
  EXPECT_DOUBLE_EQ(laser.robot_pose.x, 1.0);
  EXPECT_DOUBLE_EQ(laser.ipc_timestamp, 99.5);
  EXPECT_DOUBLE_EQ(laser.logger_timestamp, 99.6);

  // The remission count must fit the line too.
  const std::string reason = errorOf(
      "ROBOTLASER1 0 -1.5708 3.14159 0.0174533 81.9 0.01 0 2 1.0 2.0 9 10 20 "
      "1.2 0.0 0.1 1.0 0.0 0.1 0.3 0.05 0.55 0.1 0.2 99.5 host 99.6");
  EXPECT_NE(reason.find("num_remissions is 9"), std::string::npos) << reason;
  EXPECT_NE(errorOf("ROBOTLASER1 0 -1.5 3.1 0 81.9 0.01 0 1 1.0 0 1 0 0 1 0 0 0 0 0 0 0 1 h 1")
                .find("angular_resolution is not positive"),
            std::string::npos);
}

TEST(CarmenLine, OtherLines) {
  const auto param = parseCarmenLine("PARAM robot_frontlaser_offset -0.04 nohost 0");
  ASSERT_TRUE(std::holds_alternative<ParamLine>(param));
  EXPECT_EQ(std::get<ParamLine>(param).name, "robot_frontlaser_offset");
  EXPECT_EQ(std::get<ParamLine>(param).value, "-0.04");
  EXPECT_NE(errorOf("PARAM lonely").find("PARAM"), std::string::npos);
  EXPECT_EQ(std::get<SkippedLine>(parseCarmenLine("NEFF 30")).message, "NEFF");
  EXPECT_EQ(std::get<SkippedLine>(parseCarmenLine("# message formats")).message, "#");
  EXPECT_EQ(std::get<SkippedLine>(parseCarmenLine("##   (ODOM)")).message, "#");
  EXPECT_EQ(std::get<SkippedLine>(parseCarmenLine("   ")).message, "");
  EXPECT_EQ(laserOf("FLASER 1 2 0 0 0 0 0 0 1 h 1\r").ranges.size(), 1u);  // CRLF
  EXPECT_EQ(laserOf("FLASER\t1\t2  0 0 0 0 0 0 1 h 1").ranges.size(), 1u);
}

TEST(CarmenLog, ReadsAStreamWithLineNumbersAndErrors) {
  std::istringstream text(
      "# a comment\n"
      "PARAM robot_front_laser_max 80.99 nohost 0\n"
      "ODOM 0 0 0 0 0 0 1.0 h 1.0\n"
      "FLASER 2 1 2 0 0 0 0 0 0 1.5 h 1.5\n"
      "NEFF 30\n"
      "FLASER 9 1 2 0 0 0 0 0 0 2.0 h 2.0\n"
      "PARAM robot_front_laser_max 10 nohost 0\n"
      "FLASER 2 3 4 0 0 0 0 0 0 2.5 h 2.5");  // no final newline
  const rfm::tools::CarmenLog log = rfm::tools::readCarmenLog(text);
  EXPECT_EQ(log.lines, 8u);
  ASSERT_EQ(log.lasers.size(), 2u);
  EXPECT_EQ(log.lasers[0].line_number, 4u);
  EXPECT_EQ(log.lasers[1].line_number, 8u);
  ASSERT_EQ(log.odometry.size(), 1u);
  EXPECT_EQ(log.odometry[0].line_number, 3u);
  EXPECT_EQ(log.params.at("robot_front_laser_max"), "10");
  EXPECT_EQ(log.skipped.at("NEFF"), 1u);
  EXPECT_EQ(log.skipped.at("#"), 1u);
  EXPECT_EQ(log.malformed_lines, 1u);
  ASSERT_EQ(log.errors.size(), 1u);
  EXPECT_EQ(log.errors[0].rfind("line 6: FLASER: num_readings is 9", 0), 0u) << log.errors[0];
}

TEST(CarmenLog, ErrorsBeyondTheReportedOnesAreCounted) {
  std::string text;
  for (int i = 0; i < 50; ++i)
    text += "ODOM broken\n";
  std::istringstream in(text);
  const rfm::tools::CarmenLog log = rfm::tools::readCarmenLog(in);
  EXPECT_EQ(log.malformed_lines, 50u);
  EXPECT_EQ(log.errors.size(), rfm::tools::CarmenLog::kMaxReportedErrors);
}

}  // namespace
