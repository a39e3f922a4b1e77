#include "reflectance_field_map/sim/trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rfm::sim {
namespace {

double wrapAngle(double angle) {
  return std::atan2(std::sin(angle), std::cos(angle));
}

}  // namespace

Eigen::Vector2d Pose2::transform(const Eigen::Vector2d& local) const {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {x + c * local.x() - s * local.y(), y + s * local.x() + c * local.y()};
}

Pose2 Pose2::compose(const Pose2& local) const {
  const Eigen::Vector2d p = transform(local.position());
  return {p.x(), p.y(), wrapAngle(yaw + local.yaw)};
}

RobotTrajectory::RobotTrajectory(const TrajectorySpec& spec, double horizon) {
  if (spec.waypoints.empty()) throw std::invalid_argument("robot path needs at least one waypoint");
  if (!(spec.speed > 0.0)) throw std::invalid_argument("robot speed must be positive");
  if (!(spec.turn_rate > 0.0)) throw std::invalid_argument("robot turn rate must be positive");

  const auto& points = spec.waypoints;
  double yaw = 0.0;
  if (spec.initial_yaw) {
    yaw = *spec.initial_yaw;
  } else if (points.size() > 1) {
    const Eigen::Vector2d first_leg = points[1] - points[0];
    yaw = std::atan2(first_leg.y(), first_leg.x());
  }
  initial_ = {points[0].x(), points[0].y(), wrapAngle(yaw)};
  Pose2 current = initial_;
  double time = std::max(0.0, spec.start_delay);
  if (points.size() < 2) return;

  std::size_t target = 1;
  while (time < horizon) {
    const Eigen::Vector2d goal = points[target];
    const Eigen::Vector2d leg = goal - current.position();
    const double distance = leg.norm();
    if (distance > 1e-9) {
      const double turn = wrapAngle(std::atan2(leg.y(), leg.x()) - current.yaw);
      if (std::abs(turn) > 1e-9) {
        const double duration = std::abs(turn) / spec.turn_rate;
        phases_.push_back(
            {time, time + duration, current, 0.0, std::copysign(spec.turn_rate, turn)});
        time += duration;
        current.yaw = wrapAngle(current.yaw + turn);
      }
      const double duration = distance / spec.speed;
      phases_.push_back({time, time + duration, current, spec.speed, 0.0});
      time += duration;
      path_length_ += distance;
      current.x = goal.x();
      current.y = goal.y();
    }
    if (target < spec.pauses.size() && spec.pauses[target] > 0.0) {
      phases_.push_back({time, time + spec.pauses[target], current, 0.0, 0.0});
      time += spec.pauses[target];
    }
    ++target;
    if (target == points.size()) {
      if (!spec.loop) break;
      target = 0;
    }
  }
}

RobotState RobotTrajectory::stateAt(double t) const {
  if (phases_.empty() || t <= phases_.front().start_time) {
    return {phases_.empty() ? initial_ : phases_.front().start, 0.0, 0.0};
  }
  auto after =
      std::upper_bound(phases_.begin(), phases_.end(), t,
                       [](double time, const Phase& phase) { return time < phase.start_time; });
  const Phase& phase = *(after - 1);
  if (t >= phase.end_time) {  // after the last phase, or in a gap (none are created)
    const double dt = phase.end_time - phase.start_time;
    Pose2 end = phase.start;
    end.x += phase.linear_velocity * dt * std::cos(end.yaw);
    end.y += phase.linear_velocity * dt * std::sin(end.yaw);
    end.yaw = wrapAngle(end.yaw + phase.angular_velocity * dt);
    return {end, 0.0, 0.0};
  }
  const double dt = t - phase.start_time;
  Pose2 pose = phase.start;
  pose.x += phase.linear_velocity * dt * std::cos(pose.yaw);
  pose.y += phase.linear_velocity * dt * std::sin(pose.yaw);
  pose.yaw = wrapAngle(pose.yaw + phase.angular_velocity * dt);
  return {pose, phase.linear_velocity, phase.angular_velocity};
}

}  // namespace rfm::sim
