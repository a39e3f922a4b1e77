// The planar transforms the node tests publish on /tf and /tf_static.
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>

#include <cmath>
#include <string>

namespace rfm_test {

// parent -> child: (x, y, z) and a rotation of `yaw` about z, stamped `stamp`.
inline geometry_msgs::TransformStamped makeTransform(const std::string& parent,
                                                     const std::string& child, double x, double y,
                                                     double yaw, const ros::Time& stamp,
                                                     double z = 0.0) {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = parent;
  t.header.stamp = stamp;
  t.child_frame_id = child;
  t.transform.translation.x = x;
  t.transform.translation.y = y;
  t.transform.translation.z = z;
  t.transform.rotation.z = std::sin(yaw / 2);
  t.transform.rotation.w = std::cos(yaw / 2);
  return t;
}

}  // namespace rfm_test
