#include "conversions.h"

#include <algorithm>
#include <cmath>

namespace rfm {
namespace offline {
namespace {

float lastAngle(const LaserScan2D& scan) {
  return scan.angle_min +
         scan.angle_increment * static_cast<float>(std::max<size_t>(scan.ranges.size(), 1) - 1);
}

}  // namespace

LaserScan2D toLaserScan2D(const sensor_msgs::LaserScan& msg, bool* reversed) {
  LaserScan2D scan;
  scan.angle_min = msg.angle_min;
  scan.angle_increment = msg.angle_increment;
  scan.range_min = msg.range_min;
  scan.range_max = msg.range_max;
  scan.ranges = msg.ranges;
  const bool flip = msg.angle_increment < 0.0f && !msg.ranges.empty();
  if (flip) {
    scan.angle_min = lastAngle(scan);
    scan.angle_increment = -msg.angle_increment;
    std::reverse(scan.ranges.begin(), scan.ranges.end());
  }
  scan.angle_max = lastAngle(scan);
  if (reversed) *reversed = flip;
  return scan;
}

void mirrorScan(LaserScan2D& scan, bool* reversed) {
  const float last = lastAngle(scan);
  scan.angle_min = -last;
  std::reverse(scan.ranges.begin(), scan.ranges.end());
  scan.angle_max = lastAngle(scan);
  if (reversed) *reversed = !*reversed;
}

Pose2D toPose2D(const geometry_msgs::Transform& transform) {
  const auto& q = transform.rotation;
  Pose2D pose;
  pose.position = {transform.translation.x, transform.translation.y};
  pose.yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
  return pose;
}

bool isUpsideDown(const geometry_msgs::Transform& transform) {
  const auto& q = transform.rotation;
  const double norm2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  if (norm2 <= 0.0) return false;
  // z component of the rotated z axis.
  return 1.0 - 2.0 * (q.x * q.x + q.y * q.y) / norm2 < 0.0;
}

}  // namespace offline
}  // namespace rfm
