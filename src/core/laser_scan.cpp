#include "reflectance_field_map/core/laser_scan.h"

#include <cmath>
#include <sstream>

namespace rfm {

std::string LaserScan2D::validate() const {
  std::ostringstream why;
  if (!std::isfinite(angle_min) || !std::isfinite(angle_max) || !std::isfinite(angle_increment)) {
    why << "non-finite angles";
  } else if (angle_increment <= 0.0f) {
    why << "angle_increment " << angle_increment << " must be > 0";
  } else if (!std::isfinite(range_min) || !std::isfinite(range_max) || range_min < 0.0f ||
             range_max <= range_min) {
    why << "range limits [" << range_min << ", " << range_max << "] are not 0 <= min < max";
  } else if (ranges.empty()) {
    why << "no ranges";
  } else {
    // Drivers differ on whether angle_max is the last beam or one step past it.
    const double span_beams = (static_cast<double>(angle_max) - angle_min) / angle_increment;
    const double expected = span_beams + 1.0;
    const double count = static_cast<double>(ranges.size());
    if (count > expected + 0.5 || count < expected - 1.5) {
      why << ranges.size() << " ranges but the angles [" << angle_min << ", " << angle_max
          << "] step " << angle_increment << " give " << std::lround(expected);
    }
  }
  return why.str();
}

BeamReading classifyBeam(float range, float range_min, float range_max) {
  if (std::isnan(range)) return BeamReading::kInvalid;
  if (std::isinf(range)) return range > 0 ? BeamReading::kNoReturn : BeamReading::kInvalid;
  if (range < range_min) return BeamReading::kInvalid;
  if (range >= range_max) return BeamReading::kNoReturn;
  return BeamReading::kReturn;
}

void scanToRays(const LaserScan2D& scan, const Pose2D& sensor_pose, const InsertionOptions& options,
                std::vector<Ray>& rays) {
  rays.clear();
  rays.reserve(scan.ranges.size());
  const double clearing = std::min<double>(options.clearing_distance, scan.range_max);
  for (size_t beam = 0; beam < scan.ranges.size(); ++beam) {
    const float range = scan.ranges[beam];
    const BeamReading reading = classifyBeam(range, scan.range_min, scan.range_max);
    if (reading == BeamReading::kInvalid) continue;
    const bool hit = reading == BeamReading::kReturn;
    const double length = hit ? range : clearing;
    if (length <= 0.0) continue;
    Ray ray;
    ray.angle = sensor_pose.yaw + scan.angle_min + beam * static_cast<double>(scan.angle_increment);
    ray.origin = sensor_pose.position;
    ray.end = ray.origin + length * Eigen::Vector2d(std::cos(ray.angle), std::sin(ray.angle));
    ray.beam = static_cast<uint32_t>(beam);
    ray.hit = hit;
    rays.push_back(ray);
  }
}

}  // namespace rfm
