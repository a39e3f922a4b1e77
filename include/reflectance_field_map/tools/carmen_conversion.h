#pragma once

// Turns a CARMEN log into timed scans, base poses and odometry, ready for a bag (ROS-free):
// the beams' angles, no-return readings, the laser mounts and a monotonic clock.

#include "reflectance_field_map/tools/carmen_clock.h"
#include "reflectance_field_map/tools/carmen_log.h"

#include <cstddef>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfm::tools {

// The log holds nothing to convert (no laser line).
class ConversionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ConversionOptions {
  std::optional<double> max_range;          // m: readings at or beyond it are no return
  std::optional<double> field_of_view_deg;  // FLASER/RLASER: beams spread evenly over it
  std::optional<double> synthetic_period;   // s between scans when the stamps are unusable
};

// Angle of beam i: angle_min + i * angle_increment, in the laser's frame.
struct ScanGeometry {
  double angle_min = 0.0;
  double angle_increment = 0.0;
  std::string origin;  // how it was found, for the user
};

// The angles of n FLASER/RLASER beams, which the line does not give: --fov if given (centred),
// else the log's PARAM laser_{front,rear}_laser_fov and _resolution (deg, centred) when they fit
// the beam count, else CARMEN's own convention for the count (180/181: 1 deg steps, 360/361:
// 0.5 deg steps, both from -90 deg; 400/401: 0.25 deg over 100 deg, centred), else 180 deg from
// -90 deg (CARMEN's guess).
ScanGeometry oldLaserGeometry(std::size_t beams, const std::map<std::string, std::string>& params,
                              bool rear, std::optional<double> field_of_view_deg);

// Where a laser's no-return readings start.
struct NoReturnThreshold {
  double threshold = 0.0;  // readings >= this are no return; +inf: none are
  double range_max = 0.0;  // the LaserScan's range_max
  std::string note;
};

// The sensor's max-range code: the largest reading, when it recurs (10 times or more), and
// every reading within 0.2 % below it (a SICK reports 81.83-81.91 m or 32.759-32.767 m codes
// for no return). Without such a code nothing is taken for no return.
NoReturnThreshold detectNoReturnThreshold(const std::vector<const LaserLine*>& lines);

// Poses as 2D rigid transforms: compose(a, b) is b expressed in a's parent frame.
Pose2D compose(const Pose2D& a, const Pose2D& b);
Pose2D inverse(const Pose2D& p);

struct ConvertedScan {
  bool rear = false;
  double time = 0.0;
  double angle_min = 0.0;
  double angle_increment = 0.0;
  double range_max = 0.0;
  std::vector<float> ranges;       // +inf: no return; NaN: no measurement (0 or negative)
  std::vector<float> intensities;  // ROBOTLASER1 remissions when there is one per beam
  Pose2D base_pose;                // odom -> base_link at `time`
  std::size_t line_number = 0;
};

struct ConvertedOdometry {
  double time = 0.0;
  Pose2D pose;
  double translational_velocity = 0.0;
  double rotational_velocity = 0.0;
  std::size_t line_number = 0;
};

struct CarmenConversion {
  std::vector<ConvertedScan> scans;  // file order, times strictly increasing
  std::vector<ConvertedOdometry> odometry;
  std::optional<Pose2D> front_mount;  // base_link -> laser
  std::optional<Pose2D> rear_mount;   // base_link -> laser_rear
  ClockSource clock_source = ClockSource::kSynthetic;
  std::vector<std::string> notes;  // everything decided, for the user
};

// Throws ConversionError when the log has no laser line.
CarmenConversion convertCarmenLog(const CarmenLog& log, const ConversionOptions& options);

}  // namespace rfm::tools
