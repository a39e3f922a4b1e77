// A logger that keeps a scan only after the robot has moved or turned enough since the last scan
// it kept, as CARMEN's corrected logs do (a scan every metre or so). ROS-free.
#pragma once

#include <cstddef>
#include <vector>

#include "reflectance_field_map/sim/trajectory.h"

namespace rfm::sim {

struct ScanLoggerSpec {
  double keep_every_m = 0.0;    // keep a scan once the robot is this far from the last kept one
  double keep_every_deg = 0.0;  // ... or has turned this much (0: that criterion is off)
  bool enabled() const { return keep_every_m > 0.0 || keep_every_deg > 0.0; }
  // Throws std::invalid_argument naming the offending parameter.
  void validate() const;
};

class ScanLogger {
 public:
  ScanLogger(const ScanLoggerSpec& spec, std::size_t lidar_count);

  // Whether lidar `lidar`'s scan, taken with the robot at odometry pose `pose`, is kept. Each
  // lidar keeps its first scan and then one whenever a threshold is passed since its last kept
  // scan. Without a threshold every scan is kept.
  bool keep(std::size_t lidar, const Pose2& pose);

 private:
  ScanLoggerSpec spec_;
  std::vector<bool> started_;
  std::vector<Pose2> last_kept_;
};

}  // namespace rfm::sim
