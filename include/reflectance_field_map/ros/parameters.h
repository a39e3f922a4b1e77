#pragma once

#include "reflectance_field_map/core/options.h"

#include <ros/node_handle.h>

#include <string>
#include <vector>

namespace rfm::ros_glue {

// Everything the live mapper (node and nodelet) reads from its private namespace. Defaults and
// allowed ranges are documented in config/default.yaml; the core options are read through
// rfm::optionFields() under their own names.
struct RosParameters {
  std::vector<std::string> scan_topics{"/scan_front", "/scan_rear"};
  std::string fixed_frame = "odom";      // REP-105 frame the map is built in
  std::string base_frame = "base_link";  // robot frame: centre of the active region
  double map_publish_rate = 0.0333;      // Hz (every 30 s), full /rfm/map when changed
  double marker_publish_rate = 1.0;      // Hz, /rfm/*_markers; 0 disables
  double stats_publish_rate = 1.0;       // Hz, /rfm/stats
  double tf_tolerance = 0.0;             // s, TF must reach stamp + tolerance before a scan is used
  int tf_queue_size = 20;                // scans per topic waiting for their transform
  double min_scan_rate = 2.0;            // Hz, diagnostics warn when a scan topic is slower
  double max_scan_rate = 1000.0;         // Hz, diagnostics warn when a scan topic is faster
  double time_jump_threshold = 0.5;      // s, ROS time going back more than this resets the map
  double max_robot_speed = 5.0;   // m/s, a robot pose farther from the last than this allows is
                                  // rejected (plus rfm::kPoseJumpSlack)
  double max_map_extent = 400.0;  // m, side of the box the explored map may span
  std::string map_directory = "~/.ros/rfm";  // ~save_map and ~load_map work only under it
  rfm::MapperOptions mapper;

  // Throws rfm::InvalidOption naming the parameter, its value and the allowed range.
  void validate() const;
};

// Reads the private parameters of `private_nh` (defaults for unset ones) and validates them.
// Throws rfm::InvalidOption naming the parameter on a wrong type or an out-of-range value.
RosParameters readParameters(const ros::NodeHandle& private_nh);

// Names of every parameter readParameters() understands (ROS node parameters + core options).
std::vector<std::string> knownParameterNames();

// Private parameters set under `private_nh` that readParameters() does not know (typos).
std::vector<std::string> unknownParameters(const ros::NodeHandle& private_nh);

// Last component of a topic name: "/robot/scan_front" -> "scan_front".
std::string topicLeaf(const std::string& topic);

}  // namespace rfm::ros_glue
