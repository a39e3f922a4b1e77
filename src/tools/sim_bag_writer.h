// Writes a simulation run into a rosbag: scans, ground truth, TF, static TF and odometry.
#pragma once

#include <rosbag/bag.h>

#include <string>

#include "reflectance_field_map/sim/simulator.h"

namespace rfm::tools {

struct BagWriterOptions {
  double time_origin = 1000.0;  // bag/stamp time of scene time 0 (not 0: tf dislikes t=0)
  double odom_rate_hz = 50.0;
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  // With odometry drift, the true localisation map -> odom is on /tf too (a perfect localiser).
  std::string map_frame = "map";
  std::string truth_topic = "/sim/ray_truth";
};

// A SimulationSink that writes every sample to an open bag. Throws rosbag::BagException on
// write errors.
class SimBagWriter : public rfm::sim::SimulationSink {
 public:
  SimBagWriter(rosbag::Bag& bag, const rfm::sim::Scene& scene, BagWriterOptions options);

  void onRobotState(double time, const rfm::sim::RobotState& truth,
                    const rfm::sim::Pose2& odometry) override;
  void onScan(const rfm::sim::SimScan& scan, const rfm::sim::LidarSpec& lidar) override;

 private:
  void writeStaticTransforms();

  rosbag::Bag& bag_;
  const rfm::sim::Scene& scene_;
  BagWriterOptions options_;
  double next_odom_time_ = 0.0;
};

// Simulates `scene` with `seed` into a new bag at `path` (overwritten). Throws
// rosbag::BagException if the file cannot be written.
rfm::sim::SimulationSummary writeSimulationBag(const rfm::sim::Scene& scene, std::uint32_t seed,
                                               const std::string& path,
                                               const BagWriterOptions& options = {});

}  // namespace rfm::tools
