// Wheel odometry that drifts from the true path: what the robot believes it did, published as
// odom -> base_link and /odom. The beams are still traced from the true pose. ROS-free.
#pragma once

#include <cstdint>
#include <random>

#include "reflectance_field_map/sim/trajectory.h"

namespace rfm::sim {

// Error model of the odometry, applied to every step of true motion (body frame). Random walks
// grow with the square root of the distance driven or the angle turned; systematic errors with
// the distance or angle themselves. The defaults are a calibrated wheelchair's wheel odometry:
// about 1 % of the distance, and a degree or two of heading after 25 m and half a dozen turns.
struct OdometryDrift {
  bool enabled = false;              // off: odometry equals the true path
  double xy_noise = 0.005;           // m per sqrt(m) driven, along and across the heading
  double yaw_noise_deg = 0.1;        // deg per sqrt(m) driven
  double turn_noise_deg = 0.05;      // deg per sqrt(deg) turned
  double scale_error = 0.01;         // distances read this much too long (negative: too short)
  double turn_scale_error = 0.005;   // turns read this much too large
  double yaw_bias_deg_per_m = 0.02;  // heading creeps this much per metre (unequal wheels)

  // Throws std::invalid_argument naming the offending parameter.
  void validate() const;
};

class OdometryModel {
 public:
  // Starts at the true pose `start`; `seed` drives the random walks.
  OdometryModel(const OdometryDrift& drift, const Pose2& start, std::uint32_t seed);

  // Integrates the true motion from the previous true pose to `truth`, with its errors, and
  // returns the odometry pose. Without drift it returns `truth` itself.
  Pose2 advance(const Pose2& truth);
  const Pose2& pose() const { return odometry_; }

 private:
  OdometryDrift drift_;
  Pose2 previous_truth_;
  Pose2 odometry_;
  std::mt19937 rng_;
};

}  // namespace rfm::sim
