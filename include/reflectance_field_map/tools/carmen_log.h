#pragma once

// Reader of CARMEN log files (the text format of the Radish data sets), ROS-free. Every count
// read from a line is checked against the fields the line holds before it is used.

#include <cstddef>
#include <istream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace rfm::tools {

struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

enum class LaserMessage {
  kFlaser,      // FLASER: front laser, old format
  kRlaser,      // RLASER: rear laser, old format
  kRobotLaser1  // ROBOTLASER1: front laser with its own geometry
};

const char* toString(LaserMessage message);

// Geometry carried by a ROBOTLASER1 line (FLASER and RLASER lines carry none).
struct LineScanGeometry {
  double start_angle = 0.0;         // rad
  double field_of_view = 0.0;       // rad
  double angular_resolution = 0.0;  // rad between beams
  double maximum_range = 0.0;       // m
};

// FLASER n r1..rn x y theta odom_x odom_y odom_theta ipc_timestamp host [logger_timestamp]
// RLASER: the same. ROBOTLASER1 type start fov resolution max_range accuracy remission_mode
// n r1..rn m e1..em laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv
// forward_safety side_safety turn_axis ipc_timestamp host [logger_timestamp].
struct LaserLine {
  LaserMessage message = LaserMessage::kFlaser;
  std::vector<double> ranges;      // as written (m); not-a-number and signs kept
  std::vector<double> remissions;  // ROBOTLASER1 only
  std::optional<LineScanGeometry> geometry;
  Pose2D laser_pose;  // the laser's pose (corrected, in a corrected log)
  Pose2D robot_pose;  // the robot's pose the line gives beside it
  double ipc_timestamp = 0.0;
  double logger_timestamp = 0.0;  // ipc_timestamp when the line has none
  std::size_t line_number = 0;    // 1-based, set by readCarmenLog
};

// ODOM x y theta tv rv accel ipc_timestamp host [logger_timestamp]
struct OdometryLine {
  Pose2D pose;
  double translational_velocity = 0.0;
  double rotational_velocity = 0.0;
  double acceleration = 0.0;
  double ipc_timestamp = 0.0;
  double logger_timestamp = 0.0;
  std::size_t line_number = 0;
};

// PARAM name value ...
struct ParamLine {
  std::string name;
  std::string value;
};

// A line this reader does not convert: blank, a comment, or another message (NEFF, SYNC,
// TRUEPOS, RAWLASER1, ...). `message` is its first word ("" for blank, "#" for comments).
struct SkippedLine {
  std::string message;
};

// A line of a known message that does not hold what its message needs.
struct LineError {
  std::string reason;
};

using ParsedLine = std::variant<SkippedLine, LaserLine, OdometryLine, ParamLine, LineError>;

// Parses the text of one line (without its newline; a trailing '\r' is ignored). Never throws
// for any input and allocates no more than the line's own size suggests: the fuzzing entry point.
ParsedLine parseCarmenLine(std::string_view line);

// Everything read from a log, each kind in file order.
struct CarmenLog {
  std::vector<LaserLine> lasers;
  std::vector<OdometryLine> odometry;
  std::map<std::string, std::string> params;   // the last value of each name
  std::map<std::string, std::size_t> skipped;  // per first word: lines not converted
  std::size_t lines = 0;
  std::size_t malformed_lines = 0;
  // The first kMaxReportedErrors malformed lines: "line N: reason".
  std::vector<std::string> errors;
  static constexpr std::size_t kMaxReportedErrors = 20;
};

// Reads a whole log. Malformed lines are counted and reported in `errors`, not converted.
CarmenLog readCarmenLog(std::istream& in);

}  // namespace rfm::tools
