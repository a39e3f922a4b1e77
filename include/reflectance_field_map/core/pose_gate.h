#pragma once

#include <Eigen/Core>

namespace rfm {

// m, how much farther than the speed limit allows a pose may move: a localiser's corrections,
// stamp jitter between lidars.
constexpr double kPoseJumpSlack = 0.5;

// Rejects a robot position farther from the last one it accepted than a speed limit allows in
// the time between them (plus a fixed slack for localiser corrections and stamp jitter): a TF
// glitch that puts the robot a kilometre away for a second never reaches the map. The allowance
// grows with the time since the last accepted position, so a robot that really was moved (or a
// localiser that settled elsewhere) is followed again once it could have got there.
class PoseGate {
 public:
  // max_speed in m/s (> 0), slack in m (>= 0).
  PoseGate(double max_speed, double slack);

  // True (and `position` becomes the last accepted one) when it is plausible; the first position
  // after construction or reset() always is. A non-finite position never is.
  bool accept(double stamp, const Eigen::Vector2d& position);
  void reset() { has_last_ = false; }

  // Distance of the last rejected position from the last accepted one (m).
  double lastRejectedJump() const { return last_rejected_jump_; }

 private:
  double max_speed_;
  double slack_;
  bool has_last_ = false;
  double last_stamp_ = 0.0;
  Eigen::Vector2d last_position_ = Eigen::Vector2d::Zero();
  double last_rejected_jump_ = 0.0;
};

}  // namespace rfm
