// rfm_node: the live Reflectance Field Map (see MapperRos for topics, services, parameters).
#include "reflectance_field_map/ros/mapper_ros.h"

#include <ros/ros.h>

#include <memory>

int main(int argc, char** argv) {
  ros::init(argc, argv, "rfm_node");
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  std::unique_ptr<rfm::ros_glue::MapperRos> mapper;
  try {
    mapper = std::make_unique<rfm::ros_glue::MapperRos>(nh, private_nh);
  } catch (const rfm::InvalidOption& e) {
    ROS_FATAL("rfm_node: %s", rfm::ros_glue::MapperRos::describeParameterError(e).c_str());
    return 2;
  } catch (const std::exception& e) {
    ROS_FATAL("rfm_node: cannot start: %s", e.what());
    return 1;
  }
  // One thread: scan insertion, motion removal, publishing and services never overlap.
  ros::spin();
  return 0;
}
