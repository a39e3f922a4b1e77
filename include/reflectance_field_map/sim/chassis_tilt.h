// Pitch and roll of the robot's chassis over time: floor bumps rock it while it drives, and it
// settles when it stands. Every lidar on the chassis tilts with it. ROS-free.
#pragma once

#include <cstdint>
#include <vector>

#include "reflectance_field_map/sim/beam_physics.h"
#include "reflectance_field_map/sim/lidar.h"
#include "reflectance_field_map/sim/trajectory.h"

namespace rfm::sim {

class ChassisTilt {
 public:
  // Draws pitch and roll as two independent Gauss-Markov processes (correlation time
  // physics.bump_correlation_s) whose spread grows from physics.standing_tilt_deg at rest to
  // physics.bump_tilt_deg at 0.5 m/s and faster. Sampled every 5 ms over [0, duration].
  ChassisTilt(const RealisticPhysics& physics, const RobotTrajectory& trajectory, double duration,
              std::uint32_t seed);

  // Tilt at time t, interpolated between samples (held before the first and after the last).
  Tilt at(double t) const;

 private:
  double period_ = 0.005;
  std::vector<Tilt> samples_;
};

}  // namespace rfm::sim
