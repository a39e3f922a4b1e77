#include "reflectance_field_map/tools/carmen_conversion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace rfm::tools {
namespace {

constexpr double kDeg = M_PI / 180.0;
// A max-range code recurs at least this often.
constexpr std::size_t kMinCodeCount = 10;
// Codes lie within this share below the largest reading.
constexpr double kCodeBand = 0.002;
// Offsets from the robot pose to the laser pose that agree this well are one mount.
constexpr double kMountTolerance = 0.01;        // m
constexpr double kMountAngleTolerance = 0.005;  // rad
// The synthetic clock's robot: a scan every so many seconds at these speeds.
constexpr double kSyntheticSpeed = 0.3;     // m/s
constexpr double kSyntheticTurnRate = 0.5;  // rad/s
constexpr double kShortestSyntheticPeriod = 0.05;
constexpr double kLongestSyntheticPeriod = 10.0;

double normalizeAngle(double a) {
  return std::remainder(a, 2.0 * M_PI);
}

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), pattern, value);
  return text;
}

std::string formatPose(const Pose2D& p) {
  char text[128];
  std::snprintf(text, sizeof(text), "(%.3f m, %.3f m, %.2f deg)", p.x, p.y, p.theta / kDeg);
  return text;
}

std::optional<double> paramNumber(const std::map<std::string, std::string>& params,
                                  const std::string& name) {
  const auto it = params.find(name);
  if (it == params.end()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !std::isfinite(value)) return std::nullopt;
  return value;
}

double median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + static_cast<long>(values.size() / 2),
                   values.end());
  return values[values.size() / 2];
}

Pose2D medianPose(const std::vector<Pose2D>& poses) {
  std::vector<double> xs, ys, turns;
  for (const Pose2D& p : poses) {
    xs.push_back(p.x);
    ys.push_back(p.y);
    turns.push_back(normalizeAngle(p.theta - poses[0].theta));
  }
  return {median(xs), median(ys), normalizeAngle(poses[0].theta + median(turns))};
}

bool allNear(const std::vector<Pose2D>& poses, const Pose2D& centre, double tolerance,
             double angle_tolerance) {
  return std::all_of(poses.begin(), poses.end(), [&](const Pose2D& p) {
    return std::hypot(p.x - centre.x, p.y - centre.y) <= tolerance &&
           std::abs(normalizeAngle(p.theta - centre.theta)) <= angle_tolerance;
  });
}

bool isIdentity(const Pose2D& p) {
  return std::hypot(p.x, p.y) <= kMountTolerance && std::abs(p.theta) <= kMountAngleTolerance;
}

// The base trajectory at time t, linear between its samples, held beyond its ends.
Pose2D interpolate(const std::vector<double>& times, const std::vector<Pose2D>& poses, double t) {
  const auto after = std::lower_bound(times.begin(), times.end(), t);
  if (after == times.begin()) return poses.front();
  if (after == times.end()) return poses.back();
  const std::size_t i = static_cast<std::size_t>(after - times.begin());
  const double span = times[i] - times[i - 1];
  const double f = span > 0.0 ? (t - times[i - 1]) / span : 0.0;
  const Pose2D& a = poses[i - 1];
  const Pose2D& b = poses[i];
  return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y),
          normalizeAngle(a.theta + f * normalizeAngle(b.theta - a.theta))};
}

// Seconds between scans of a synthetic clock: the median time the scans' steps take at a
// walking robot's speed and turn rate.
double syntheticPeriod(const std::vector<const LaserLine*>& scans) {
  std::vector<double> steps;
  for (std::size_t i = 1; i < scans.size(); ++i) {
    const Pose2D& a = scans[i - 1]->laser_pose;
    const Pose2D& b = scans[i]->laser_pose;
    steps.push_back(std::max(std::hypot(b.x - a.x, b.y - a.y) / kSyntheticSpeed,
                             std::abs(normalizeAngle(b.theta - a.theta)) / kSyntheticTurnRate));
  }
  if (steps.empty()) return 1.0;
  return std::clamp(median(steps), kShortestSyntheticPeriod, kLongestSyntheticPeriod);
}

std::vector<float> convertRanges(const std::vector<double>& ranges, double threshold,
                                 std::size_t& no_return, std::size_t& no_measurement) {
  std::vector<float> out;
  out.reserve(ranges.size());
  for (const double r : ranges) {
    if (!(r > 0.0) || std::isnan(r)) {
      out.push_back(std::numeric_limits<float>::quiet_NaN());
      ++no_measurement;
    } else if (r >= threshold) {
      out.push_back(std::numeric_limits<float>::infinity());
      ++no_return;
    } else {
      out.push_back(static_cast<float>(r));
    }
  }
  return out;
}

}  // namespace

Pose2D compose(const Pose2D& a, const Pose2D& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, normalizeAngle(a.theta + b.theta)};
}

Pose2D inverse(const Pose2D& p) {
  const double c = std::cos(p.theta), s = std::sin(p.theta);
  return {-(c * p.x + s * p.y), -(-s * p.x + c * p.y), normalizeAngle(-p.theta)};
}

ScanGeometry oldLaserGeometry(std::size_t beams, const std::map<std::string, std::string>& params,
                              bool rear, std::optional<double> field_of_view_deg) {
  const std::string n = std::to_string(beams) + " beams";
  const double steps = beams > 1 ? static_cast<double>(beams - 1) : 1.0;
  if (field_of_view_deg) {
    return {-0.5 * *field_of_view_deg * kDeg, *field_of_view_deg * kDeg / steps,
            n + " over " + format("%g deg", *field_of_view_deg) + " (--fov), centred"};
  }
  const std::string prefix = rear ? "laser_rear_laser_" : "laser_front_laser_";
  const std::optional<double> fov = paramNumber(params, prefix + "fov");
  const std::optional<double> resolution = paramNumber(params, prefix + "resolution");
  std::string param_note;
  if (fov && resolution && *fov > 0.0 && *resolution > 0.0) {
    const double spans = *fov / *resolution;  // beams - 1 for 181 over 180, beams for 180
    if (std::abs(spans - steps) <= 0.5 || std::abs(spans - static_cast<double>(beams)) <= 0.5) {
      return {-0.5 * *fov * kDeg, *resolution * kDeg,
              n + " at " + format("%g deg", *resolution) + " over " + format("%g deg", *fov) +
                  " (PARAM " + prefix + "fov and _resolution), centred"};
    }
    param_note = "; PARAM " + prefix + "fov " + format("%g", *fov) + " at " +
                 format("%g", *resolution) + " deg does not fit " + n;
  }
  switch (beams) {
    case 180:
    case 181:
      return {-90.0 * kDeg, 1.0 * kDeg,
              n + ": CARMEN's convention, 1 deg steps from -90 deg" + param_note};
    case 360:
    case 361:
      return {-90.0 * kDeg, 0.5 * kDeg,
              n + ": CARMEN's convention, 0.5 deg steps from -90 deg" + param_note};
    case 400:
    case 401:
      return {-50.0 * kDeg, 0.25 * kDeg,
              n + ": CARMEN's convention, 0.25 deg steps over 100 deg, centred" + param_note};
    default:
      return {-90.0 * kDeg, 180.0 * kDeg / steps,
              n +
                  ": no PARAM gives the field of view, taken as 180 deg as CARMEN does (--fov "
                  "sets it)" +
                  param_note};
  }
}

NoReturnThreshold detectNoReturnThreshold(const std::vector<const LaserLine*>& lines) {
  double largest = -std::numeric_limits<double>::infinity();
  std::size_t readings = 0;
  for (const LaserLine* line : lines) {
    for (const double r : line->ranges) {
      if (std::isfinite(r) && r > 0.0) {
        largest = std::max(largest, r);
        ++readings;
      }
    }
  }
  NoReturnThreshold result;
  if (readings == 0) {
    result.threshold = std::numeric_limits<double>::infinity();
    result.range_max = 1.0;
    result.note = "no positive reading at all";
    return result;
  }
  const double threshold = largest * (1.0 - kCodeBand);
  std::size_t at_largest = 0, in_band = 0;
  std::map<double, std::size_t> codes;
  for (const LaserLine* line : lines) {
    for (const double r : line->ranges) {
      at_largest += r == largest;
      if (std::isfinite(r) && r >= threshold) {
        ++in_band;
        if (codes.size() < 8 || codes.count(r)) ++codes[r];
      }
    }
  }
  if (at_largest < kMinCodeCount) {
    result.threshold = std::numeric_limits<double>::infinity();
    result.range_max = largest * (1.0 + kCodeBand) + 0.01;
    result.note = "no max-range code (the largest reading, " + format("%g m", largest) +
                  ", occurs " + std::to_string(at_largest) + " times): every reading is a return";
    return result;
  }
  result.threshold = threshold;
  result.range_max = threshold;
  std::string values;
  for (const auto& [value, count] : codes)
    values += (values.empty() ? "" : ", ") + format("%g m", value) + " x" + std::to_string(count);
  result.note = std::to_string(in_band) + " readings of " + std::to_string(readings) +
                " at or above " + format("%.3f m", threshold) +
                " are the sensor's max-range code (" + values + "): no return (+inf)";
  return result;
}

namespace {

// The lasers' lines: the front laser's are ROBOTLASER1 when the log has them (they carry their
// geometry), else FLASER; the rear laser's RLASER.
struct LaserLines {
  std::vector<const LaserLine*> front, rear;
};

LaserLines selectLasers(const CarmenLog& log, CarmenConversion& out) {
  const bool robot_laser = std::any_of(log.lasers.begin(), log.lasers.end(), [](const auto& l) {
    return l.message == LaserMessage::kRobotLaser1;
  });
  LaserLines lasers;
  std::size_t dropped_flaser = 0;
  for (const LaserLine& line : log.lasers) {
    if (line.message == LaserMessage::kRlaser) {
      lasers.rear.push_back(&line);
    } else if (robot_laser && line.message == LaserMessage::kFlaser) {
      ++dropped_flaser;
    } else {
      lasers.front.push_back(&line);
    }
  }
  if (lasers.front.empty() && lasers.rear.empty()) {
    throw ConversionError("the log has no FLASER, RLASER or ROBOTLASER1 line");
  }
  if (dropped_flaser > 0) {
    out.notes.push_back("front laser: ROBOTLASER1 lines; the " + std::to_string(dropped_flaser) +
                        " FLASER lines beside them are not converted");
  }
  return lasers;
}

// Times every laser line (into scan_time) and ODOM line (into out.odometry).
void timeLines(const CarmenLog& log, const LaserLines& lasers, const ConversionOptions& options,
               std::map<const LaserLine*, double>& scan_time, CarmenConversion& out) {
  struct Timed {
    std::size_t line_number;
    const LaserLine* laser;
    const OdometryLine* odometry;
  };
  std::vector<Timed> timed;
  for (const LaserLine* line : lasers.front)
    timed.push_back({line->line_number, line, nullptr});
  for (const LaserLine* line : lasers.rear)
    timed.push_back({line->line_number, line, nullptr});
  for (const OdometryLine& line : log.odometry)
    timed.push_back({line.line_number, nullptr, &line});
  std::sort(timed.begin(), timed.end(),
            [](const Timed& a, const Timed& b) { return a.line_number < b.line_number; });
  std::vector<StampedLine> stamped;
  for (const Timed& t : timed) {
    const double ipc = t.laser ? t.laser->ipc_timestamp : t.odometry->ipc_timestamp;
    const double logger = t.laser ? t.laser->logger_timestamp : t.odometry->logger_timestamp;
    stamped.push_back({ipc, logger, t.laser != nullptr, t.line_number});
  }

  ClockOptions clock_options;
  if (options.synthetic_period) {
    clock_options.synthetic_period = *options.synthetic_period;
  } else {
    // One laser's steps (the rear one's poses differ from the front one's by the mount); with
    // two lasers the lines share the period.
    const std::vector<const LaserLine*>& one = lasers.front.empty() ? lasers.rear : lasers.front;
    clock_options.synthetic_period = syntheticPeriod(one) * static_cast<double>(one.size()) /
                                     static_cast<double>(lasers.front.size() + lasers.rear.size());
  }
  const CarmenClock clock = buildCarmenClock(stamped, clock_options);
  out.clock_source = clock.source;
  out.notes.insert(out.notes.end(), clock.notes.begin(), clock.notes.end());
  if (clock.source == ClockSource::kSynthetic && !options.synthetic_period) {
    // Right after the note that says the clock is synthesised.
    out.notes.insert(out.notes.end() - static_cast<long>(clock.notes.size()) + 1,
                     "clock: " + format("%.3f s", clock_options.synthetic_period) +
                         " a laser line is the median time of the scans' steps at " +
                         format("%g m/s", kSyntheticSpeed) + " and " +
                         format("%.0f deg/s", kSyntheticTurnRate / kDeg) + " (--period sets it)");
  }
  for (std::size_t i = 0; i < timed.size(); ++i) {
    if (timed[i].laser) {
      scan_time[timed[i].laser] = clock.times[i];
    } else {
      const OdometryLine& o = *timed[i].odometry;
      out.odometry.push_back(
          {clock.times[i], o.pose, o.translational_velocity, o.rotational_velocity, o.line_number});
    }
  }
}

// The mounts (out.front_mount, out.rear_mount) and each laser line's base pose. The laser pose
// of each line is what the corrected log fixes; the robot pose beside it is the robot's when it
// keeps one offset from the laser pose.
void placeLasers(const LaserLines& lasers, const std::map<const LaserLine*, double>& scan_time,
                 std::map<const LaserLine*, Pose2D>& base_pose, CarmenConversion& out) {
  std::vector<double> front_times;
  std::vector<Pose2D> front_bases;
  if (!lasers.front.empty()) {
    std::vector<Pose2D> offsets;
    for (const LaserLine* line : lasers.front)
      offsets.push_back(compose(inverse(line->robot_pose), line->laser_pose));
    const Pose2D offset = medianPose(offsets);
    const bool one_mount = allNear(offsets, offset, kMountTolerance, kMountAngleTolerance);
    out.front_mount = one_mount ? offset : Pose2D{};
    if (one_mount && isIdentity(offset)) {
      out.notes.push_back(
          "front laser: the lines' two poses agree: base_link is the laser's (corrected) pose, "
          "base_link -> laser is the identity");
    } else if (one_mount) {
      out.notes.push_back("front laser: the lines keep the laser at " + formatPose(offset) +
                          " from the robot pose: base_link is the robot pose, base_link -> laser "
                          "that offset");
    } else {
      out.notes.push_back(
          "front laser: the lines' second pose drifts from the laser pose (raw odometry): "
          "base_link is the laser's (corrected) pose, base_link -> laser is the identity");
    }
    for (const LaserLine* line : lasers.front) {
      const Pose2D base = compose(line->laser_pose, inverse(*out.front_mount));
      base_pose[line] = base;
      front_times.push_back(scan_time.at(line));
      front_bases.push_back(base);
    }
  }
  if (lasers.rear.empty()) return;
  std::vector<Pose2D> direct;
  for (const LaserLine* line : lasers.rear)
    direct.push_back(compose(inverse(line->robot_pose), line->laser_pose));
  const Pose2D direct_offset = medianPose(direct);
  const bool front_is_robot = out.front_mount && !isIdentity(*out.front_mount);
  if (lasers.front.empty()) {
    out.rear_mount = Pose2D{};
    out.notes.push_back("rear laser: no front laser: base_link is the rear laser's pose");
  } else if (front_is_robot && !isIdentity(direct_offset) &&
             allNear(direct, direct_offset, kMountTolerance, kMountAngleTolerance)) {
    out.rear_mount = direct_offset;
    out.notes.push_back("rear laser: the lines keep it at " + formatPose(direct_offset) +
                        " from the robot pose: base_link -> laser_rear");
  } else {
    // The rear laser's pose against base_link where the front scans put it at that time.
    std::vector<Pose2D> seen;
    for (const LaserLine* line : lasers.rear) {
      seen.push_back(compose(inverse(interpolate(front_times, front_bases, scan_time.at(line))),
                             line->laser_pose));
    }
    out.rear_mount = medianPose(seen);
    std::vector<double> deviations;
    for (const Pose2D& p : seen)
      deviations.push_back(std::hypot(p.x - out.rear_mount->x, p.y - out.rear_mount->y));
    out.notes.push_back("rear laser: base_link -> laser_rear " + formatPose(*out.rear_mount) +
                        ", the median of the rear poses against the front trajectory (median "
                        "deviation " +
                        format("%.3f m", median(deviations)) + ")");
  }
  for (const LaserLine* line : lasers.rear)
    base_pose[line] = compose(line->laser_pose, inverse(*out.rear_mount));
}

// One laser's scans: angles, no-return readings, time and base pose.
void convertScans(const CarmenLog& log, const std::vector<const LaserLine*>& lines, bool is_rear,
                  const ConversionOptions& options,
                  const std::map<const LaserLine*, double>& scan_time,
                  const std::map<const LaserLine*, Pose2D>& base_pose, CarmenConversion& out) {
  if (lines.empty()) return;
  const std::string who = is_rear ? "rear laser: " : "front laser: ";
  NoReturnThreshold no_return;
  if (options.max_range) {
    no_return.threshold = *options.max_range;
    no_return.range_max = *options.max_range;
    no_return.note = "readings at or above " + format("%g m", *options.max_range) +
                     " (--max-range) are no return (+inf)";
  } else {
    no_return = detectNoReturnThreshold(lines);
    if (lines.front()->geometry) {
      no_return.note =
          "readings at or above each ROBOTLASER1 line's maximum_range are no return (where a "
          "line gives none: " +
          no_return.note + ")";
    }
  }
  out.notes.push_back(who + no_return.note);
  std::map<std::size_t, std::string> geometries;
  std::size_t no_returns = 0, no_measurements = 0;
  for (const LaserLine* line : lines) {
    ConvertedScan scan;
    scan.rear = is_rear;
    scan.time = scan_time.at(line);
    scan.base_pose = base_pose.at(line);
    scan.line_number = line->line_number;
    double threshold = no_return.threshold;
    scan.range_max = no_return.range_max;
    if (line->geometry) {
      scan.angle_min = line->geometry->start_angle;
      scan.angle_increment = line->geometry->angular_resolution;
      if (!options.max_range && line->geometry->maximum_range > 0.0) {
        threshold = line->geometry->maximum_range;
        scan.range_max = threshold;
      }
    } else {
      const ScanGeometry geometry =
          oldLaserGeometry(line->ranges.size(), log.params, is_rear, options.field_of_view_deg);
      scan.angle_min = geometry.angle_min;
      scan.angle_increment = geometry.angle_increment;
      geometries.emplace(line->ranges.size(), geometry.origin);
    }
    scan.ranges = convertRanges(line->ranges, threshold, no_returns, no_measurements);
    if (line->remissions.size() == line->ranges.size()) {
      scan.intensities.assign(line->remissions.begin(), line->remissions.end());
    }
    out.scans.push_back(std::move(scan));
  }
  for (const auto& [beams, origin] : geometries)
    out.notes.push_back(who + origin);
  out.notes.push_back(who + std::to_string(lines.size()) + " scans, " + std::to_string(no_returns) +
                      " readings no return (+inf), " + std::to_string(no_measurements) +
                      " not positive (NaN)");
}

}  // namespace

CarmenConversion convertCarmenLog(const CarmenLog& log, const ConversionOptions& options) {
  CarmenConversion out;
  const LaserLines lasers = selectLasers(log, out);
  std::map<const LaserLine*, double> scan_time;
  timeLines(log, lasers, options, scan_time, out);
  std::map<const LaserLine*, Pose2D> base_pose;
  placeLasers(lasers, scan_time, base_pose, out);
  convertScans(log, lasers.front, false, options, scan_time, base_pose, out);
  convertScans(log, lasers.rear, true, options, scan_time, base_pose, out);
  std::sort(out.scans.begin(), out.scans.end(), [](const ConvertedScan& a, const ConvertedScan& b) {
    return a.line_number < b.line_number;
  });
  return out;
}

}  // namespace rfm::tools
