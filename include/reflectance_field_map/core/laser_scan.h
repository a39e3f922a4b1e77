#pragma once

#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/options.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rfm {

// A planar scan in the sensor frame, as sensor_msgs/LaserScan without ROS.
struct LaserScan2D {
  float angle_min = 0.0f;        // rad, first beam
  float angle_max = 0.0f;        // rad, last beam
  float angle_increment = 0.0f;  // rad between beams (> 0)
  float range_min = 0.0f;        // m
  float range_max = 0.0f;        // m
  std::vector<float> ranges;     // REP-117: +inf no return, -inf too close, NaN invalid
  // How far the sensor moved while it swept, in the fixed frame (m): from where the first listed
  // beam was measured to where the last one was; zero for a scan taken from one place. The rays
  // share an origin in the middle of that path, so return k is moved by (k / (beams - 1) - 1/2)
  // of it from where its range ends along its beam (compensateSweepMotion).
  Eigen::Vector2d sweep_shift = Eigen::Vector2d::Zero();

  // Empty when usable, otherwise why not (malformed geometry).
  std::string validate() const;
};

// The two functions below keep angle_max's span from angle_min, so validate() judges the beam
// count as before (drivers differ on what angle_max means).
// For a scan whose angle_increment is negative: the same beams, each keeping its direction,
// in reverse order, swept with a positive increment.
void reverseBeamOrder(LaserScan2D& scan);
// For a laser mounted upside down (its z axis pointing down), which sweeps clockwise seen from
// above: the scan as seen from above, beams reversed and angles negated.
void mirrorScan(LaserScan2D& scan);

// A lidar measures its beams one after another while it moves (REP-117 time_increment); a scan
// stamped at one pose smears what the sensor saw while it turned (a 10 Hz lidar turning at
// 50 deg/s draws a wall 10 m away up to 0.9 m off). Given the sensor's poses when the sweep began
// (`sensor_pose`, on entry) and ended, the beams' directions are turned as the sensor turned,
// evenly over the sweep (the increment changes, the beams stay evenly spaced so that rays still
// share one origin), the origin moves to the middle of the sweep's path, and `sweep_shift` takes
// the path, so that each return lands where its beam was measured from. `beam0_last`: the
// beams are in the reverse of their measured order (a reversed or upside-down scan). Returns
// false, changing nothing, when the scan cannot be turned so (fewer than two beams, or a sensor
// turning against its sweep faster than it sweeps).
bool compensateSweepMotion(LaserScan2D& scan, Pose2D& sensor_pose, const Pose2D& sweep_end_pose,
                           bool beam0_last);

// How long after its stamp (its first beam, REP-117) a scan's last beam was measured:
// (beams - 1) * |time_increment|; 0 when the message gives no usable sweep (time_increment zero
// or not finite, or a sweep over `kMaxSweepSeconds`).
constexpr double kMaxSweepSeconds = 1.0;
double sweepSeconds(double time_increment, size_t beams);

// One beam ready for insertion, in the fixed frame.
struct Ray {
  Eigen::Vector2d origin;
  Eigen::Vector2d end;  // hit point, or the end of the cleared stretch when !hit
  double angle = 0.0;   // direction of travel, rad
  uint32_t beam = 0;    // index in its scan
  bool hit = false;     // end is a return (adds a hit) or only the end of misses
};

// Per-beam label, values as in msg/RayLabels.msg.
enum class RayLabel : uint8_t { kNoReturn = 0, kKept = 1, kMotion = 2, kReflection = 3 };

// What a beam's range says (REP-117).
enum class BeamReading : uint8_t {
  kInvalid,   // NaN, -inf, below range_min: changes nothing
  kReturn,    // in [range_min, range_max): misses then a hit
  kNoReturn,  // +inf or >= range_max: misses up to the clearing distance, no hit
};

inline BeamReading classifyBeam(float range, float range_min, float range_max) {
  if (std::isnan(range)) return BeamReading::kInvalid;
  if (std::isinf(range)) return range > 0 ? BeamReading::kNoReturn : BeamReading::kInvalid;
  if (range < range_min) return BeamReading::kInvalid;
  if (range >= range_max) return BeamReading::kNoReturn;
  return BeamReading::kReturn;
}

// Calls visit(ray) with the ray of each usable beam of a scan taken at sensor_pose (fixed
// frame), in beam order; invalid beams are skipped. Inline, so that a caller needing only part
// of each ray (the recording's extent needs only ends) neither stores nor computes the rest.
template <typename Visit>
void forEachBeamRay(const LaserScan2D& scan, const Pose2D& sensor_pose,
                    const InsertionOptions& options, Visit&& visit) {
  const double clearing = std::min<double>(options.clearing_distance, scan.range_max);
  const double increment = scan.angle_increment;
  const double first_angle = sensor_pose.yaw + scan.angle_min;
  // Beam directions by rotating the previous one by the increment, which is far cheaper than a
  // sincos per beam; an exact sincos every few beams keeps the rounding near 1e-15.
  constexpr size_t kExactEvery = 32;
  const Eigen::Vector2d step(std::cos(increment), std::sin(increment));
  Eigen::Vector2d direction;
  // A swept scan's returns move with the sensor along the sweep (LaserScan2D::sweep_shift).
  const bool swept = !scan.sweep_shift.isZero(0.0) && scan.ranges.size() > 1;
  const double per_beam = swept ? 1.0 / static_cast<double>(scan.ranges.size() - 1) : 0.0;
  for (size_t beam = 0; beam < scan.ranges.size(); ++beam) {
    const double angle = first_angle + beam * increment;
    if (beam % kExactEvery == 0) {
      direction = {std::cos(angle), std::sin(angle)};
    } else {
      direction = {direction.x() * step.x() - direction.y() * step.y(),
                   direction.x() * step.y() + direction.y() * step.x()};
    }
    const BeamReading reading = classifyBeam(scan.ranges[beam], scan.range_min, scan.range_max);
    if (reading == BeamReading::kInvalid) continue;
    const bool hit = reading == BeamReading::kReturn;
    const double length = hit ? scan.ranges[beam] : clearing;
    if (length <= 0.0) continue;
    Ray ray;
    ray.angle = angle;
    ray.origin = sensor_pose.position;
    ray.end = ray.origin + length * direction;
    if (hit && swept) ray.end += (static_cast<double>(beam) * per_beam - 0.5) * scan.sweep_shift;
    ray.beam = static_cast<uint32_t>(beam);
    ray.hit = hit;
    visit(ray);
  }
}

// The rays of forEachBeamRay, appended to `rays` (cleared first) in beam order.
void scanToRays(const LaserScan2D& scan, const Pose2D& sensor_pose, const InsertionOptions& options,
                std::vector<Ray>& rays);

// Beam indices first..last, both included.
struct BeamRange {
  uint32_t first, last;
};
// The beams of a scan taken from `origin` (beam k heading first_beam_angle + k * increment,
// increment > 0) whose rays may cross `box`: those within the angular extent, seen from there,
// of the box grown by `end_spread` (m: how far a ray may stray from its beam's line, as a swept
// scan's returns do), with a margin of two beams: ascending and disjoint (the extent may straddle
// beam 0's direction, and a scan may span over a turn), or one range holding every beam when the
// origin lies within a cell of that box. Written to `ranges` (cleared first); indices past the
// scan's last beam simply match nothing.
void beamsTowardsBox(const CellBox& box, double resolution, const Eigen::Vector2d& origin,
                     double first_beam_angle, double increment, double end_spread,
                     std::vector<BeamRange>& ranges);

}  // namespace rfm
