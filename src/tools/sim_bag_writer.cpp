#include "sim_bag_writer.h"

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <reflectance_field_map/RayTruth.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <boost/make_shared.hpp>
#include <cmath>

namespace rfm::tools {
namespace {

geometry_msgs::Quaternion yawQuaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.x = 0.0;
  q.y = 0.0;
  q.z = std::sin(yaw / 2.0);
  q.w = std::cos(yaw / 2.0);
  return q;
}

geometry_msgs::TransformStamped planarTransform(const ros::Time& stamp, const std::string& parent,
                                                const std::string& child,
                                                const rfm::sim::Pose2& pose) {
  geometry_msgs::TransformStamped transform;
  transform.header.stamp = stamp;
  transform.header.frame_id = parent;
  transform.child_frame_id = child;
  transform.transform.translation.x = pose.x;
  transform.transform.translation.y = pose.y;
  transform.transform.translation.z = 0.0;
  transform.transform.rotation = yawQuaternion(pose.yaw);
  return transform;
}

rfm::sim::Pose2 inverse(const rfm::sim::Pose2& pose) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  return {-(c * pose.x + s * pose.y), s * pose.x - c * pose.y, -pose.yaw};
}

}  // namespace

SimBagWriter::SimBagWriter(rosbag::Bag& bag, const rfm::sim::Scene& scene, BagWriterOptions options)
    : bag_(bag), scene_(scene), options_(std::move(options)) {
  writeStaticTransforms();
}

void SimBagWriter::writeStaticTransforms() {
  tf2_msgs::TFMessage message;
  const ros::Time stamp(options_.time_origin);
  for (const rfm::sim::LidarSpec& lidar : scene_.lidars) {
    geometry_msgs::TransformStamped transform;
    transform.header.stamp = stamp;
    transform.header.frame_id = options_.base_frame;
    transform.child_frame_id = lidar.frame_id;
    transform.transform.translation.x = lidar.mount_x;
    transform.transform.translation.y = lidar.mount_y;
    transform.transform.translation.z = lidar.mount_z;
    transform.transform.rotation = yawQuaternion(lidar.mount_yaw);
    message.transforms.push_back(transform);
  }
  // Latched like tf2_ros::StaticTransformBroadcaster, so `rosbag play` re-delivers it.
  auto header = boost::make_shared<ros::M_string>();
  (*header)["callerid"] = "/rfm_sim";
  (*header)["latching"] = "1";
  (*header)["topic"] = "/tf_static";
  (*header)["md5sum"] = ros::message_traits::MD5Sum<tf2_msgs::TFMessage>::value();
  (*header)["type"] = ros::message_traits::DataType<tf2_msgs::TFMessage>::value();
  (*header)["message_definition"] = ros::message_traits::Definition<tf2_msgs::TFMessage>::value();
  bag_.write("/tf_static", stamp, message, header);
}

void SimBagWriter::onRobotState(double time, const rfm::sim::RobotState& truth,
                                const rfm::sim::Pose2& odometry) {
  const ros::Time stamp(options_.time_origin + time);
  tf2_msgs::TFMessage tf_message;
  tf_message.transforms.push_back(
      planarTransform(stamp, options_.odom_frame, options_.base_frame, odometry));
  if (scene_.odometry.enabled) {
    // map -> odom = truth * odometry^-1, so that map -> base_link is the true pose.
    const rfm::sim::Pose2 inverse_odometry = inverse(odometry);
    tf_message.transforms.push_back(planarTransform(stamp, options_.map_frame, options_.odom_frame,
                                                    truth.pose.compose(inverse_odometry)));
  }
  bag_.write("/tf", stamp, tf_message);

  if (time + 1e-9 < next_odom_time_) return;
  next_odom_time_ += 1.0 / options_.odom_rate_hz;
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = options_.odom_frame;
  odom.child_frame_id = options_.base_frame;
  odom.pose.pose.position.x = odometry.x;
  odom.pose.pose.position.y = odometry.y;
  odom.pose.pose.orientation = yawQuaternion(odometry.yaw);
  odom.twist.twist.linear.x = truth.linear_velocity;
  odom.twist.twist.angular.z = truth.angular_velocity;
  // Tiny but non-zero covariances keep consumers' matrix code well-defined.
  for (const int i : {0, 7, 14, 21, 28, 35}) {
    odom.pose.covariance[i] = 1e-6;
    odom.twist.covariance[i] = 1e-6;
  }
  bag_.write("/odom", stamp, odom);
}

void SimBagWriter::onScan(const rfm::sim::SimScan& scan, const rfm::sim::LidarSpec& lidar) {
  const ros::Time stamp(options_.time_origin + scan.time);
  sensor_msgs::LaserScan message;
  message.header.stamp = stamp;
  message.header.frame_id = lidar.frame_id;
  message.angle_min = static_cast<float>(lidar.angle_min);
  message.angle_max = static_cast<float>(lidar.angleMax());
  message.angle_increment = static_cast<float>(lidar.angle_increment);
  message.time_increment = static_cast<float>(lidar.timeIncrement());  // 0: all at the stamp
  message.scan_time = static_cast<float>(1.0 / lidar.rate_hz);
  message.range_min = static_cast<float>(lidar.range_min);
  message.range_max = static_cast<float>(lidar.range_max);
  message.ranges = scan.ranges;
  bag_.write(lidar.topic, stamp, message);

  reflectance_field_map::RayTruth truth;
  truth.header = message.header;
  truth.scan_topic = lidar.topic;
  truth.classes = scan.classes;
  bag_.write(options_.truth_topic, stamp, truth);
}

rfm::sim::SimulationSummary writeSimulationBag(const rfm::sim::Scene& scene, std::uint32_t seed,
                                               const std::string& path,
                                               const BagWriterOptions& options) {
  rosbag::Bag bag;
  bag.open(path, rosbag::bagmode::Write);
  bag.setCompression(rosbag::compression::LZ4);
  BagWriterOptions effective = options;
  effective.odom_rate_hz = scene.odom_rate_hz;
  SimBagWriter writer(bag, scene, effective);
  rfm::sim::Simulator simulator(scene, seed);
  const rfm::sim::SimulationSummary summary = simulator.run(writer);
  bag.close();
  return summary;
}

}  // namespace rfm::tools
