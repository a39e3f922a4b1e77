// A robot with two lidars (front and rear, 360 beams each over 180 degrees) driving back and
// forth along y = 0 in a 12 m x 8 m room (or out of it, far enough), published live to the node:
// odometry as TF odom -> base_link, the lasers in /tf_static, one scan per lidar per tick, stamped
// with ROS time (the test's /clock under simulated time). What a fault test needs to change is a
// switch: transforms late or missing, a lidar silent, the odometry jumped, the whole world paused.
#pragma once

#include "tf_messages.h"

#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <mutex>
#include <thread>
#include <utility>

namespace rfm_test {

constexpr double kRoomHalfX = 6.0;
constexpr double kRoomHalfY = 4.0;

// Range from (ox, oy) along `angle` to the room's walls.
inline float roomRange(double ox, double oy, double angle) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  double t = std::numeric_limits<double>::infinity();
  if (dx > 1e-9) t = std::min(t, (kRoomHalfX - ox) / dx);
  if (dx < -1e-9) t = std::min(t, (-kRoomHalfX - ox) / dx);
  if (dy > 1e-9) t = std::min(t, (kRoomHalfY - oy) / dy);
  if (dy < -1e-9) t = std::min(t, (-kRoomHalfY - oy) / dy);
  return static_cast<float>(t);
}

class RoomWorld {
 public:
  static constexpr int kBeams = 360;
  static constexpr double kSweepSeconds = 0.02;
  static constexpr double kLaserOffset = 0.3;  // lasers at +-0.3 m in base_link

  // `clock` gives the stamps: ROS time by default, the test's own clock under simulated time.
  explicit RoomWorld(
      ros::NodeHandle& nh, std::function<ros::Time()> clock = [] { return ros::Time::now(); })
      : clock_(std::move(clock)) {
    front_pub_ = nh.advertise<sensor_msgs::LaserScan>("/scan_front", 1000);
    rear_pub_ = nh.advertise<sensor_msgs::LaserScan>("/scan_rear", 1000);
    tf_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 1000);
    static_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf_static", 1, true);
  }
  ~RoomWorld() { stop(); }

  bool connected() const {
    return front_pub_.getNumSubscribers() > 0 && rear_pub_.getNumSubscribers() > 0 &&
           tf_pub_.getNumSubscribers() > 0 && static_pub_.getNumSubscribers() > 0;
  }

  // Publishes the lasers' transforms, then a tick every `period` s of wall time.
  void start(double period = 0.025) {
    tf2_msgs::TFMessage statics;
    const ros::Time now = clock_();
    statics.transforms.push_back(
        makeTransform("base_link", "laser_front", kLaserOffset, 0.0, 0.0, now));
    statics.transforms.push_back(
        makeTransform("base_link", "laser_rear", -kLaserOffset, 0.0, M_PI, now));
    static_pub_.publish(statics);
    running_ = true;
    thread_ = std::thread([this, period] {
      ros::WallRate rate(1.0 / period);
      while (running_ && ros::ok()) {
        if (!paused_) tick();
        rate.sleep();  // pacing the lidars, as live drivers are
      }
    });
  }
  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }

  // Switches (take effect at the next tick).
  std::atomic<bool> paused_{false};
  std::atomic<bool> rear_silent_{false};
  std::atomic<bool> tf_missing_{false};   // odometry not published at all
  std::atomic<double> tf_delay_{0.0};     // s, odometry published this late
  std::atomic<double> odom_jump_x_{0.0};  // m, added to the odometry (a TF glitch)
  std::atomic<double> half_range_{3.0};   // m, the drive turns at x = +-half_range_

  // Scans published so far (both lidars, every kind), and those with the odometry jumped.
  uint64_t published() const { return published_; }
  uint64_t jumpedScans() const { return jumped_scans_; }

  // Publishes one front scan now, stamped `stamp`, numbered like the others: for faults that
  // are single messages (a stale scan, a burst).
  void publishFront(const ros::Time& stamp, int beams = kBeams) {
    std::lock_guard<std::mutex> lock(mutex_);
    publishScanLocked(true, stamp, beams);
  }
  // Odometry at `stamp` with the robot where it stands now.
  void publishOdometry(const ros::Time& stamp) {
    std::lock_guard<std::mutex> lock(mutex_);
    tf2_msgs::TFMessage odom;
    odom.transforms.push_back(makeTransform("odom", "base_link", x_, 0.0, 0.0, stamp));
    tf_pub_.publish(odom);
    odometry_stamp_ = stamp;
  }
  ros::Time lastStamp() {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_stamp_;
  }

 private:
  void tick() {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::Time now = clock_();
    // The clock has not moved since the last tick, or odometry holds this stamp already (tf2
    // would ignore a second transform at it, and the tick's scans would take the first).
    if (now == last_stamp_ || now == odometry_stamp_) return;
    // After the clock jumps back the robot carries on from where it is, and odometry held back
    // for later is forgotten.
    if (now < last_stamp_) pending_tf_.clear();
    const double dt =
        last_stamp_.isZero() ? 0.0 : std::clamp((now - last_stamp_).toSec(), 0.0, 0.1);
    last_stamp_ = now;
    // Back and forth between x = -half_range_ and half_range_ at 0.5 m/s.
    x_ += direction_ * 0.5 * dt;
    if (std::fabs(x_) > half_range_) direction_ = x_ > 0.0 ? -1.0 : 1.0;
    const double jump = odom_jump_x_;
    if (jump != 0.0) jumped_scans_ += rear_silent_ ? 1 : 2;
    if (!tf_missing_) pending_tf_.emplace_back(now, x_ + jump);
    while (!pending_tf_.empty() && pending_tf_.front().first + ros::Duration(tf_delay_) <= now) {
      tf2_msgs::TFMessage odom;
      odom.transforms.push_back(makeTransform("odom", "base_link", pending_tf_.front().second, 0.0,
                                              0.0, pending_tf_.front().first));
      tf_pub_.publish(odom);
      pending_tf_.pop_front();
    }
    publishScanLocked(true, now, kBeams);
    if (!rear_silent_) publishScanLocked(false, now, kBeams);
  }

  void publishScanLocked(bool front, const ros::Time& stamp, int beams) {
    sensor_msgs::LaserScan scan;
    scan.header.seq = ++(front ? front_seq_ : rear_seq_);
    scan.header.stamp = stamp;
    scan.header.frame_id = front ? "laser_front" : "laser_rear";
    scan.angle_min = static_cast<float>(-M_PI / 2);
    scan.angle_increment = static_cast<float>(M_PI / beams);
    scan.angle_max = scan.angle_min + (beams - 1) * scan.angle_increment;
    scan.range_min = 0.05f;
    scan.range_max = 20.0f;
    // Swept beam by beam over 20 ms, as a Hokuyo's 25 ms revolution: the node waits for the
    // transform at the last beam too, one tick later.
    scan.time_increment = static_cast<float>(kSweepSeconds / (beams - 1));
    scan.scan_time = static_cast<float>(kSweepSeconds);
    scan.ranges.resize(static_cast<size_t>(beams));
    const double lx = x_ + (front ? kLaserOffset : -kLaserOffset);
    const double heading = front ? 0.0 : M_PI;
    for (int b = 0; b < beams; ++b) {
      scan.ranges[static_cast<size_t>(b)] =
          roomRange(lx, 0.0, heading + scan.angle_min + b * scan.angle_increment);
    }
    (front ? front_pub_ : rear_pub_).publish(scan);
    ++published_;
  }

  std::function<ros::Time()> clock_;
  ros::Publisher front_pub_, rear_pub_, tf_pub_, static_pub_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::mutex mutex_;
  ros::Time last_stamp_;
  ros::Time odometry_stamp_;  // publishOdometry's last
  double x_ = 0.0;
  double direction_ = 1.0;
  uint32_t front_seq_ = 0, rear_seq_ = 0;
  std::deque<std::pair<ros::Time, double>> pending_tf_;
  std::atomic<uint64_t> published_{0}, jumped_scans_{0};
};

}  // namespace rfm_test
