// The robot's ground-truth motion: a waypoint path driven at wheelchair speed, turning in place
// toward each next waypoint and waiting at some. ROS-free.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace rfm::sim {

struct Pose2 {
  double x = 0.0, y = 0.0, yaw = 0.0;
  Eigen::Vector2d position() const { return {x, y}; }
  // Maps a point from this pose's frame into the parent frame.
  Eigen::Vector2d transform(const Eigen::Vector2d& local) const;
  Pose2 compose(const Pose2& local) const;
};

struct RobotState {
  Pose2 pose;
  double linear_velocity = 0.0;   // forward, m/s (body frame)
  double angular_velocity = 0.0;  // rad/s
};

struct TrajectorySpec {
  std::vector<Eigen::Vector2d> waypoints;
  std::vector<double> pauses;         // s standing at each waypoint on arrival (missing: none)
  double speed = 0.7;                 // m/s while driving
  double turn_rate = 0.8;             // rad/s while turning in place
  double start_delay = 0.0;           // stands still at the first waypoint for this long
  std::optional<double> initial_yaw;  // default: facing the second waypoint
  bool loop = false;                  // drive back to the first waypoint and repeat
};

class RobotTrajectory {
 public:
  // Builds the motion up to `horizon` seconds (loops repeat until then). Throws
  // std::invalid_argument for an empty path or non-positive speeds.
  RobotTrajectory(const TrajectorySpec& spec, double horizon);

  RobotState stateAt(double t) const;
  // Time at which the robot reaches its last waypoint (it stands still afterwards).
  double motionEndTime() const { return phases_.empty() ? 0.0 : phases_.back().end_time; }
  double pathLength() const { return path_length_; }

 private:
  struct Phase {
    double start_time, end_time;
    Pose2 start;
    double linear_velocity, angular_velocity;
  };
  Pose2 initial_;
  std::vector<Phase> phases_;
  double path_length_ = 0.0;
};

}  // namespace rfm::sim
