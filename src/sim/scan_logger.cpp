#include "reflectance_field_map/sim/scan_logger.h"

#include <cmath>
#include <stdexcept>

namespace rfm::sim {

void ScanLoggerSpec::validate() const {
  if (!(keep_every_m >= 0.0 && keep_every_m <= 100.0)) {
    throw std::invalid_argument("keep_every_m must be in [0, 100]");
  }
  if (!(keep_every_deg >= 0.0 && keep_every_deg <= 360.0)) {
    throw std::invalid_argument("keep_every_deg must be in [0, 360]");
  }
}

ScanLogger::ScanLogger(const ScanLoggerSpec& spec, std::size_t lidar_count)
    : spec_(spec), started_(lidar_count, false), last_kept_(lidar_count) {
  spec_.validate();
}

bool ScanLogger::keep(std::size_t lidar, const Pose2& pose) {
  if (!spec_.enabled()) return true;
  bool kept = !started_.at(lidar);
  if (!kept) {
    const Pose2& last = last_kept_[lidar];
    const double moved = (pose.position() - last.position()).norm();
    const double turned_deg =
        std::abs(std::atan2(std::sin(pose.yaw - last.yaw), std::cos(pose.yaw - last.yaw))) * 180.0 /
        M_PI;
    kept = (spec_.keep_every_m > 0.0 && moved >= spec_.keep_every_m) ||
           (spec_.keep_every_deg > 0.0 && turned_deg >= spec_.keep_every_deg);
  }
  if (kept) {
    started_[lidar] = true;
    last_kept_[lidar] = pose;
  }
  return kept;
}

}  // namespace rfm::sim
