#include "carmen_bag_writer.h"

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <stdexcept>

namespace rfm::tools {
namespace {

geometry_msgs::Quaternion yawQuaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(0.5 * yaw);
  q.w = std::cos(0.5 * yaw);
  return q;
}

geometry_msgs::TransformStamped transform(const char* parent, const char* child,
                                          const ros::Time& stamp, const Pose2D& pose) {
  geometry_msgs::TransformStamped tf;
  tf.header.stamp = stamp;
  tf.header.frame_id = parent;
  tf.child_frame_id = child;
  tf.transform.translation.x = pose.x;
  tf.transform.translation.y = pose.y;
  tf.transform.rotation = yawQuaternion(pose.theta);
  return tf;
}

sensor_msgs::LaserScan laserScan(const ConvertedScan& scan, uint32_t seq) {
  sensor_msgs::LaserScan msg;
  msg.header.seq = seq;
  msg.header.stamp = ros::Time(scan.time);
  msg.header.frame_id = scan.rear ? kRearLaserFrame : kFrontLaserFrame;
  msg.angle_min = static_cast<float>(scan.angle_min);
  msg.angle_increment = static_cast<float>(scan.angle_increment);
  msg.angle_max = static_cast<float>(
      scan.angle_min +
      scan.angle_increment * static_cast<double>(scan.ranges.empty() ? 0 : scan.ranges.size() - 1));
  msg.range_min = 0.0f;
  msg.range_max = static_cast<float>(scan.range_max);
  msg.ranges = scan.ranges;
  msg.intensities = scan.intensities;
  return msg;
}

nav_msgs::Odometry odometry(const ConvertedOdometry& o, uint32_t seq) {
  nav_msgs::Odometry msg;
  msg.header.seq = seq;
  msg.header.stamp = ros::Time(o.time);
  msg.header.frame_id = kOdomFrame;
  msg.child_frame_id = kBaseFrame;
  msg.pose.pose.position.x = o.pose.x;
  msg.pose.pose.position.y = o.pose.y;
  msg.pose.pose.orientation = yawQuaternion(o.pose.theta);
  msg.twist.twist.linear.x = o.translational_velocity;
  msg.twist.twist.angular.z = o.rotational_velocity;
  return msg;
}

}  // namespace

void writeCarmenBag(const std::string& path, const CarmenConversion& conversion) {
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    double first = conversion.scans.empty() ? 1.0 : conversion.scans.front().time;
    if (!conversion.odometry.empty()) first = std::min(first, conversion.odometry.front().time);
    tf2_msgs::TFMessage statics;
    const ros::Time start(first);
    if (conversion.front_mount) {
      statics.transforms.push_back(
          transform(kBaseFrame, kFrontLaserFrame, start, *conversion.front_mount));
    }
    if (conversion.rear_mount) {
      statics.transforms.push_back(
          transform(kBaseFrame, kRearLaserFrame, start, *conversion.rear_mount));
    }
    bag.write("/tf_static", start, statics);

    uint32_t front_seq = 0, rear_seq = 0, odometry_seq = 0;
    auto scan = conversion.scans.begin();
    auto odom = conversion.odometry.begin();
    while (scan != conversion.scans.end() || odom != conversion.odometry.end()) {
      const bool scan_next =
          odom == conversion.odometry.end() ||
          (scan != conversion.scans.end() && scan->line_number < odom->line_number);
      if (scan_next) {
        const ros::Time stamp(scan->time);
        tf2_msgs::TFMessage tf;
        tf.transforms.push_back(transform(kOdomFrame, kBaseFrame, stamp, scan->base_pose));
        bag.write("/tf", stamp, tf);
        bag.write(scan->rear ? kRearScanTopic : kFrontScanTopic, stamp,
                  laserScan(*scan, scan->rear ? rear_seq++ : front_seq++));
        ++scan;
      } else {
        bag.write(kOdometryTopic, ros::Time(odom->time), odometry(*odom, odometry_seq++));
        ++odom;
      }
    }
    bag.close();
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("cannot write " + path + ": " + e.what());
  }
}

}  // namespace rfm::tools
