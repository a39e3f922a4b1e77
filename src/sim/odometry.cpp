#include "reflectance_field_map/sim/odometry.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "require_range.h"

namespace rfm::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

using detail::requireRange;

double wrapAngle(double angle) {
  return std::atan2(std::sin(angle), std::cos(angle));
}

}  // namespace

void OdometryDrift::validate() const {
  requireRange(xy_noise, 0.0, 1.0, "xy_noise");
  requireRange(yaw_noise_deg, 0.0, 10.0, "yaw_noise_deg");
  requireRange(turn_noise_deg, 0.0, 10.0, "turn_noise_deg");
  requireRange(scale_error, -0.2, 0.2, "scale_error");
  requireRange(turn_scale_error, -0.2, 0.2, "turn_scale_error");
  requireRange(yaw_bias_deg_per_m, -5.0, 5.0, "yaw_bias_deg_per_m");
}

OdometryModel::OdometryModel(const OdometryDrift& drift, const Pose2& start, std::uint32_t seed)
    : drift_(drift), previous_truth_(start), odometry_(start) {
  std::seed_seq sequence{seed, 0x0D0BU, 0x52464dU};
  rng_.seed(sequence);
}

Pose2 OdometryModel::advance(const Pose2& truth) {
  const bool perfect = drift_.xy_noise == 0.0 && drift_.yaw_noise_deg == 0.0 &&
                       drift_.turn_noise_deg == 0.0 && drift_.scale_error == 0.0 &&
                       drift_.turn_scale_error == 0.0 && drift_.yaw_bias_deg_per_m == 0.0;
  if (!drift_.enabled || perfect) {  // exactly the true path, not a sum of its steps
    previous_truth_ = odometry_ = truth;
    return truth;
  }
  // The true step in the frame of the previous true pose.
  const double c = std::cos(previous_truth_.yaw), s = std::sin(previous_truth_.yaw);
  const Eigen::Vector2d world_step = truth.position() - previous_truth_.position();
  const Eigen::Vector2d step(c * world_step.x() + s * world_step.y(),
                             -s * world_step.x() + c * world_step.y());
  const double turn = wrapAngle(truth.yaw - previous_truth_.yaw);
  previous_truth_ = truth;
  const double driven = step.norm();
  const double turned_deg = std::abs(turn) / kDegToRad;

  std::normal_distribution<double> standard_normal(0.0, 1.0);
  const double xy_sigma = drift_.xy_noise * std::sqrt(driven);
  const double yaw_sigma_deg =
      std::sqrt(drift_.yaw_noise_deg * drift_.yaw_noise_deg * driven +
                drift_.turn_noise_deg * drift_.turn_noise_deg * turned_deg);
  Pose2 measured_step;
  measured_step.x = step.x() * (1.0 + drift_.scale_error) + xy_sigma * standard_normal(rng_);
  measured_step.y = step.y() * (1.0 + drift_.scale_error) + xy_sigma * standard_normal(rng_);
  measured_step.yaw =
      turn * (1.0 + drift_.turn_scale_error) +
      kDegToRad * (drift_.yaw_bias_deg_per_m * driven + yaw_sigma_deg * standard_normal(rng_));
  odometry_ = odometry_.compose(measured_step);
  return odometry_;
}

}  // namespace rfm::sim
