// Runs a scene: drives the robot, moves the people and fires the lidars, handing every odometry
// sample and scan to a sink in time order. ROS-free; the bag writer is one such sink.
#pragma once

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "reflectance_field_map/sim/beam_physics.h"
#include "reflectance_field_map/sim/lidar.h"
#include "reflectance_field_map/sim/people.h"
#include "reflectance_field_map/sim/scene.h"
#include "reflectance_field_map/sim/trajectory.h"

namespace rfm::sim {

class SimulationSink {
 public:
  virtual ~SimulationSink() = default;
  // The robot's true state and its odometry pose (equal to the true pose without drift), at the
  // scene's tf rate.
  virtual void onRobotState(double time, const RobotState& truth, const Pose2& odometry) = 0;
  // One scan of lidar `scan.lidar_index`.
  virtual void onScan(const SimScan& scan, const LidarSpec& lidar) = 0;
};

// Counts of what a run produced (for logs and tests).
struct SimulationSummary {
  std::size_t robot_states = 0;
  std::size_t scans = 0;
  std::size_t scans_not_logged = 0;                       // taken but dropped by the scene's logger
  std::uint64_t beams_per_class[6] = {0, 0, 0, 0, 0, 0};  // indexed by BeamClass
  double path_length = 0.0;
  // How far the odometry had drifted from the true pose by the end of the run.
  double final_odometry_error_m = 0.0;
  double final_odometry_error_deg = 0.0;
};

class Simulator {
 public:
  Simulator(const Scene& scene, std::uint32_t seed);

  // Simulates [0, duration] scene seconds. Robot states run from 0 to slightly past the last scan
  // so every scan can be interpolated in TF.
  SimulationSummary run(SimulationSink& sink);

  const Scene& scene() const { return scene_; }
  const RobotTrajectory& trajectory() const { return trajectory_; }

 private:
  const Scene& scene_;
  RobotTrajectory trajectory_;
  std::vector<Pedestrian> people_;
  std::vector<LidarSensor> lidars_;
  BeamTracer tracer_;
  std::uint32_t seed_;
};

}  // namespace rfm::sim
