#pragma once

#include "reflectance_field_map/tools/carmen_conversion.h"

#include <string>

namespace rfm::tools {

// Frames and topics of the bag rfm_carmen2bag writes.
constexpr const char* kOdomFrame = "odom";
constexpr const char* kBaseFrame = "base_link";
constexpr const char* kFrontLaserFrame = "laser";
constexpr const char* kRearLaserFrame = "laser_rear";
constexpr const char* kFrontScanTopic = "/scan";
constexpr const char* kRearScanTopic = "/scan_rear";
constexpr const char* kOdometryTopic = "/odom";

// Writes `conversion` to a bag: /tf_static (base_link -> laser, laser_rear) first, then in file
// order /tf odom -> base_link and the scan (/scan or /scan_rear) for each laser line, and /odom
// (nav_msgs/Odometry, odom -> base_link, the ODOM line's pose and velocities) for each ODOM
// line. Messages are recorded at their stamps. Throws std::runtime_error naming the bag.
void writeCarmenBag(const std::string& path, const CarmenConversion& conversion);

}  // namespace rfm::tools
