#pragma once

// Private ROS <-> core conversions for the offline tool. They overlap with the rfm_ros
// conversions (include/reflectance_field_map/ros/conversions.h); once that library builds,
// these should go (see the offline report).

#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"

#include <geometry_msgs/Transform.h>
#include <sensor_msgs/LaserScan.h>

namespace rfm {
namespace offline {

// Copies the scan's geometry and ranges. A scan with angle_increment < 0 is reversed so the
// increment is positive; `*reversed` tells the caller to reverse per-beam results back.
// angle_max is set to the last beam's angle.
LaserScan2D toLaserScan2D(const sensor_msgs::LaserScan& msg, bool* reversed);

// Mirrors a scan about its x axis (a laser mounted upside down sweeps clockwise seen from
// above): beams reversed and angles negated, the increment stays positive. Toggles `*reversed`.
void mirrorScan(LaserScan2D& scan, bool* reversed);

// Planar part of a transform: x, y and the heading of the x axis.
Pose2D toPose2D(const geometry_msgs::Transform& transform);
// True when the transform turns the z axis downwards (an upside-down laser).
bool isUpsideDown(const geometry_msgs::Transform& transform);

}  // namespace offline
}  // namespace rfm
