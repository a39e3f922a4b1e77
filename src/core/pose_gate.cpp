#include "reflectance_field_map/core/pose_gate.h"

#include <cmath>

namespace rfm {

PoseGate::PoseGate(double max_speed, double slack) : max_speed_(max_speed), slack_(slack) {}

bool PoseGate::accept(double stamp, const Eigen::Vector2d& position) {
  if (!position.allFinite() || !std::isfinite(stamp)) return false;
  if (has_last_) {
    // Scans of several lidars interleave, so a stamp may precede the last accepted one a little.
    const double allowed = max_speed_ * std::fabs(stamp - last_stamp_) + slack_;
    const double jump = (position - last_position_).norm();
    if (jump > allowed) {
      last_rejected_jump_ = jump;
      return false;
    }
  }
  has_last_ = true;
  last_stamp_ = stamp;
  last_position_ = position;
  return true;
}

}  // namespace rfm
