#include "reflectance_field_map/sim/chassis_tilt.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace rfm::sim {

ChassisTilt::ChassisTilt(const RealisticPhysics& physics, const RobotTrajectory& trajectory,
                         double duration, std::uint32_t seed) {
  constexpr double kDegToRad = M_PI / 180.0;
  constexpr double kFullBumpSpeed = 0.5;  // m/s
  std::seed_seq sequence{seed, 0x7117U, 0x52464dU};
  std::mt19937 rng(sequence);
  std::normal_distribution<double> standard_normal(0.0, 1.0);
  const double correlation = std::exp(-period_ / physics.bump_correlation_s);
  const double innovation = std::sqrt(1.0 - correlation * correlation);
  auto spread = [&](double t) {
    const RobotState state = trajectory.stateAt(t);
    const double share = std::min(1.0, std::abs(state.linear_velocity) / kFullBumpSpeed);
    return kDegToRad * (physics.standing_tilt_deg +
                        share * (physics.bump_tilt_deg - physics.standing_tilt_deg));
  };
  const std::size_t count = static_cast<std::size_t>(std::ceil(duration / period_)) + 2;
  samples_.reserve(count);
  Tilt tilt{spread(0.0) * standard_normal(rng), spread(0.0) * standard_normal(rng)};
  for (std::size_t k = 0; k < count; ++k) {
    samples_.push_back(tilt);
    const double sigma = spread(static_cast<double>(k + 1) * period_);
    tilt.pitch = correlation * tilt.pitch + innovation * sigma * standard_normal(rng);
    tilt.roll = correlation * tilt.roll + innovation * sigma * standard_normal(rng);
  }
}

Tilt ChassisTilt::at(double t) const {
  const double position = std::clamp(t / period_, 0.0, static_cast<double>(samples_.size() - 1));
  const std::size_t below = std::min(static_cast<std::size_t>(position), samples_.size() - 2);
  const double fraction = position - static_cast<double>(below);
  const Tilt& a = samples_[below];
  const Tilt& b = samples_[below + 1];
  return {a.pitch + fraction * (b.pitch - a.pitch), a.roll + fraction * (b.roll - a.roll)};
}

}  // namespace rfm::sim
