#include "reflectance_field_map/tools/carmen_log.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <system_error>

namespace rfm::tools {
namespace {

// Splits on spaces and tabs.
std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
      ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t')
      ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

// Reads fields in order; the first failure is kept as the line's error.
class FieldCursor {
 public:
  FieldCursor(const std::vector<std::string_view>& fields, std::string message)
      : fields_(fields), message_(std::move(message)) {}

  std::size_t remaining() const { return fields_.size() - next_; }
  bool failed() const { return !error_.empty(); }
  const std::string& error() const { return error_; }
  void fail(const std::string& reason) {
    if (error_.empty()) error_ = message_ + ": " + reason;
  }

  // Any double, "nan" and "inf" included (ranges and stamps may hold them).
  double number(const char* what) {
    if (failed()) return 0.0;
    if (next_ >= fields_.size()) {
      fail(std::string("the line ends before its ") + what);
      return 0.0;
    }
    const std::string_view text = fields_[next_++];
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec == std::errc::result_out_of_range && end == text.data() + text.size()) {
      // A number beyond double's range (1e-400, 1e400): strtod saturates it to 0 or infinity.
      return std::strtod(std::string(text).c_str(), nullptr);
    }
    if (ec != std::errc() || end != text.data() + text.size()) {
      fail(std::string(what) + " '" + std::string(text.substr(0, 40)) + "' is not a number");
      return 0.0;
    }
    return value;
  }

  double finiteNumber(const char* what) {
    const double value = number(what);
    if (!failed() && !std::isfinite(value)) fail(std::string(what) + " is not finite");
    return value;
  }

  // A count of the fields that follow it, which the rest of the line must hold with `after`
  // more fields behind them.
  std::size_t count(const char* what, std::size_t after) {
    if (failed()) return 0;
    if (next_ >= fields_.size()) {
      fail(std::string("the line ends before its ") + what);
      return 0;
    }
    const std::string_view text = fields_[next_++];
    unsigned long long value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size()) {
      fail(std::string(what) + " '" + std::string(text.substr(0, 40)) +
           "' is not a count (a non-negative whole number)");
      return 0;
    }
    if (value > remaining() || remaining() - value < after) {
      const std::size_t room = remaining() > after ? remaining() - after : 0;
      fail(std::string(what) + " is " + std::to_string(value) + " but the " +
           std::to_string(remaining()) + " fields after it leave room for " + std::to_string(room));
      return 0;
    }
    return static_cast<std::size_t>(value);
  }

  std::string_view word(const char* what) {
    if (failed()) return {};
    if (next_ >= fields_.size()) {
      fail(std::string("the line ends before its ") + what);
      return {};
    }
    return fields_[next_++];
  }

  Pose2D pose(const char* what) {
    Pose2D p;
    p.x = finiteNumber(what);
    p.y = finiteNumber(what);
    p.theta = finiteNumber(what);
    return p;
  }

 private:
  const std::vector<std::string_view>& fields_;
  std::string message_;
  std::size_t next_ = 1;  // past the message name
  std::string error_;
};

// ipc_timestamp host [logger_timestamp], and nothing after.
void readStamps(FieldCursor& cursor, double& ipc, double& logger) {
  ipc = cursor.number("ipc_timestamp");
  cursor.word("hostname");
  logger = cursor.remaining() > 0 ? cursor.number("logger_timestamp") : ipc;
  if (!cursor.failed() && cursor.remaining() > 0) {
    cursor.fail(std::to_string(cursor.remaining()) + " fields after logger_timestamp");
  }
}

// Fields after the ranges of a FLASER/RLASER line: 6 pose values, ipc stamp, host (the logger
// stamp is optional).
constexpr std::size_t kOldLaserTrailer = 8;
// Fields after the remissions of a ROBOTLASER1 line: 6 pose values, tv, rv, forward and side
// safety distances, turn axis, ipc stamp, host.
constexpr std::size_t kRobotLaserTrailer = 13;

ParsedLine parseOldLaser(const std::vector<std::string_view>& fields, LaserMessage message) {
  FieldCursor cursor(fields, toString(message));
  LaserLine laser;
  laser.message = message;
  const std::size_t n = cursor.count("num_readings", kOldLaserTrailer);
  laser.ranges.reserve(n);
  for (std::size_t i = 0; i < n && !cursor.failed(); ++i)
    laser.ranges.push_back(cursor.number("range"));
  laser.laser_pose = cursor.pose("laser pose");
  laser.robot_pose = cursor.pose("robot pose");
  readStamps(cursor, laser.ipc_timestamp, laser.logger_timestamp);
  if (!cursor.failed() && n == 0) cursor.fail("num_readings is 0");
  if (cursor.failed()) return LineError{cursor.error()};
  return laser;
}

ParsedLine parseRobotLaser(const std::vector<std::string_view>& fields) {
  FieldCursor cursor(fields, toString(LaserMessage::kRobotLaser1));
  LaserLine laser;
  laser.message = LaserMessage::kRobotLaser1;
  cursor.word("laser_type");
  LineScanGeometry geometry;
  geometry.start_angle = cursor.finiteNumber("start_angle");
  geometry.field_of_view = cursor.finiteNumber("field_of_view");
  geometry.angular_resolution = cursor.finiteNumber("angular_resolution");
  geometry.maximum_range = cursor.finiteNumber("maximum_range");
  cursor.number("accuracy");
  cursor.word("remission_mode");
  // After the ranges: at least the remission count and the trailer.
  const std::size_t n = cursor.count("num_readings", 1 + kRobotLaserTrailer);
  laser.ranges.reserve(n);
  for (std::size_t i = 0; i < n && !cursor.failed(); ++i)
    laser.ranges.push_back(cursor.number("range"));
  const std::size_t m = cursor.count("num_remissions", kRobotLaserTrailer);
  laser.remissions.reserve(m);
  for (std::size_t i = 0; i < m && !cursor.failed(); ++i)
    laser.remissions.push_back(cursor.number("remission"));
  laser.laser_pose = cursor.pose("laser pose");
  laser.robot_pose = cursor.pose("robot pose");
  for (const char* what : {"tv", "rv", "forward_safety_dist", "side_safety_dist", "turn_axis"})
    cursor.number(what);
  readStamps(cursor, laser.ipc_timestamp, laser.logger_timestamp);
  if (!cursor.failed()) {
    if (n == 0) cursor.fail("num_readings is 0");
    if (!(geometry.angular_resolution > 0.0)) cursor.fail("angular_resolution is not positive");
    if (!(geometry.field_of_view > 0.0)) cursor.fail("field_of_view is not positive");
  }
  if (cursor.failed()) return LineError{cursor.error()};
  laser.geometry = geometry;
  return laser;
}

ParsedLine parseOdometry(const std::vector<std::string_view>& fields) {
  FieldCursor cursor(fields, "ODOM");
  OdometryLine odometry;
  odometry.pose = cursor.pose("pose");
  odometry.translational_velocity = cursor.number("tv");
  odometry.rotational_velocity = cursor.number("rv");
  odometry.acceleration = cursor.number("accel");
  readStamps(cursor, odometry.ipc_timestamp, odometry.logger_timestamp);
  if (cursor.failed()) return LineError{cursor.error()};
  return odometry;
}

ParsedLine parseParam(const std::vector<std::string_view>& fields) {
  if (fields.size() < 3) return LineError{"PARAM: a name and a value are needed"};
  return ParamLine{std::string(fields[1]), std::string(fields[2])};
}

}  // namespace

const char* toString(LaserMessage message) {
  switch (message) {
    case LaserMessage::kFlaser:
      return "FLASER";
    case LaserMessage::kRlaser:
      return "RLASER";
    case LaserMessage::kRobotLaser1:
      return "ROBOTLASER1";
  }
  return "?";
}

ParsedLine parseCarmenLine(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  const std::vector<std::string_view> fields = splitFields(line);
  if (fields.empty()) return SkippedLine{""};
  const std::string_view name = fields[0];
  if (name.front() == '#') return SkippedLine{"#"};
  if (name == "FLASER") return parseOldLaser(fields, LaserMessage::kFlaser);
  if (name == "RLASER") return parseOldLaser(fields, LaserMessage::kRlaser);
  if (name == "ROBOTLASER1") return parseRobotLaser(fields);
  if (name == "ODOM") return parseOdometry(fields);
  if (name == "PARAM") return parseParam(fields);
  return SkippedLine{std::string(name.substr(0, 40))};
}

CarmenLog readCarmenLog(std::istream& in) {
  CarmenLog log;
  std::string line;
  while (std::getline(in, line)) {
    ++log.lines;
    ParsedLine parsed = parseCarmenLine(line);
    if (auto* laser = std::get_if<LaserLine>(&parsed)) {
      laser->line_number = log.lines;
      log.lasers.push_back(std::move(*laser));
    } else if (auto* odometry = std::get_if<OdometryLine>(&parsed)) {
      odometry->line_number = log.lines;
      log.odometry.push_back(*odometry);
    } else if (auto* param = std::get_if<ParamLine>(&parsed)) {
      log.params[param->name] = param->value;
    } else if (auto* skipped = std::get_if<SkippedLine>(&parsed)) {
      ++log.skipped[skipped->message];
    } else if (auto* error = std::get_if<LineError>(&parsed)) {
      ++log.malformed_lines;
      if (log.errors.size() < CarmenLog::kMaxReportedErrors) {
        log.errors.push_back("line " + std::to_string(log.lines) + ": " + error->reason);
      }
    }
  }
  return log;
}

}  // namespace rfm::tools
