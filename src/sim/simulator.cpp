#include "reflectance_field_map/sim/simulator.h"

#include <cmath>
#include <limits>
#include <optional>

#include "reflectance_field_map/sim/chassis_tilt.h"
#include "reflectance_field_map/sim/odometry.h"
#include "reflectance_field_map/sim/scan_logger.h"

namespace rfm::sim {
namespace {

// The robot, its chassis tilt and the people, as the realistic sensor model asks for them.
class SceneMotion : public MovingScene {
 public:
  SceneMotion(const RobotTrajectory& trajectory, const std::vector<Pedestrian>& people,
              const ChassisTilt& tilt)
      : trajectory_(trajectory), people_(people), tilt_(tilt) {}
  Pose2 robotPose(double t) const override { return trajectory_.stateAt(t).pose; }
  Tilt chassisTilt(double t) const override { return tilt_.at(t); }
  std::vector<Circle> people(double t) const override { return peopleAt(people_, t); }

 private:
  const RobotTrajectory& trajectory_;
  const std::vector<Pedestrian>& people_;
  const ChassisTilt& tilt_;
};

}  // namespace

Simulator::Simulator(const Scene& scene, std::uint32_t seed)
    : scene_(scene),
      trajectory_(scene.robot, scene.duration),
      tracer_(scene.world, scene.materials, scene.physics),
      seed_(seed) {
  scene_.materials.validate();
  if (scene_.physics.enabled) scene_.physics.validate();
  if (scene_.odometry.enabled) scene_.odometry.validate();
  scene_.logger.validate();
  for (const PersonSpec& person : scene.people)
    people_.emplace_back(person);
  for (const LidarSpec& lidar : scene.lidars)
    lidars_.emplace_back(lidar);
}

SimulationSummary Simulator::run(SimulationSink& sink) {
  SimulationSummary summary;
  summary.path_length = trajectory_.pathLength();

  // One random stream per lidar, derived from the seed, so lidars do not perturb each other.
  std::vector<std::mt19937> lidar_rngs;
  for (std::size_t i = 0; i < lidars_.size(); ++i) {
    std::seed_seq sequence{seed_, static_cast<std::uint32_t>(i), 0x52464dU};
    lidar_rngs.emplace_back(sequence);
  }
  std::vector<std::size_t> next_scan(lidars_.size(), 0);
  const double state_period = 1.0 / scene_.tf_rate_hz;
  const double state_end = scene_.duration + 2.0 * state_period;
  std::size_t next_state = 0;
  const double window_min = scene_.materials.specular_window_min_deg * M_PI / 180.0;
  const double window_max = scene_.materials.specular_window_max_deg * M_PI / 180.0;

  // The realistic physics, drift and logger draw from streams of their own, so a scene without
  // them draws exactly what it always did.
  std::optional<ChassisTilt> chassis_tilt;
  if (scene_.physics.enabled) {
    chassis_tilt.emplace(scene_.physics, trajectory_, state_end, seed_);
  }
  const std::optional<SceneMotion> motion =
      chassis_tilt ? std::optional<SceneMotion>(std::in_place, trajectory_, people_, *chassis_tilt)
                   : std::nullopt;
  OdometryModel odometry(scene_.odometry, trajectory_.stateAt(0.0).pose, seed_);
  ScanLogger logger(scene_.logger, lidars_.size());
  RobotState last_truth = trajectory_.stateAt(0.0);

  auto scanTime = [&](std::size_t lidar, std::size_t k) {
    return lidars_[lidar].spec().time_offset +
           static_cast<double>(k) / lidars_[lidar].spec().rate_hz;
  };

  // Merge the robot-state stream and each lidar's scan stream by time (states first on ties, so a
  // consumer always has the pose of a scan's instant before the scan).
  while (true) {
    double best_time = std::numeric_limits<double>::infinity();
    int best_lidar = -1;  // -1 = robot state
    const double state_time = static_cast<double>(next_state) * state_period;
    if (state_time <= state_end) best_time = state_time;
    for (std::size_t i = 0; i < lidars_.size(); ++i) {
      const double t = scanTime(i, next_scan[i]);
      if (t <= scene_.duration && t < best_time) {
        best_time = t;
        best_lidar = static_cast<int>(i);
      }
    }
    if (!std::isfinite(best_time)) break;

    if (best_lidar < 0) {
      last_truth = trajectory_.stateAt(best_time);
      sink.onRobotState(best_time, last_truth, odometry.advance(last_truth.pose));
      ++summary.robot_states;
      ++next_state;
      continue;
    }
    const std::size_t lidar = static_cast<std::size_t>(best_lidar);
    ++next_scan[lidar];
    if (!logger.keep(lidar, odometry.pose())) {
      ++summary.scans_not_logged;
      continue;
    }
    std::mt19937& rng = lidar_rngs[lidar];
    SimScan scan;
    if (motion) {
      scan = lidars_[lidar].scanRealistic(tracer_, *motion, best_time, rng);
    } else {
      // The return window of glass and mirrors varies per scan with out-of-plane tilt.
      const double window = std::uniform_real_distribution<double>(window_min, window_max)(rng);
      scan = lidars_[lidar].scan(tracer_, trajectory_.stateAt(best_time).pose, best_time,
                                 peopleAt(people_, best_time), window, rng);
    }
    scan.lidar_index = lidar;
    for (const std::uint8_t beam_class : scan.classes)
      ++summary.beams_per_class[beam_class];
    sink.onScan(scan, lidars_[lidar].spec());
    ++summary.scans;
  }
  const Pose2& believed = odometry.pose();
  summary.final_odometry_error_m = (believed.position() - last_truth.pose.position()).norm();
  summary.final_odometry_error_deg =
      std::abs(std::atan2(std::sin(believed.yaw - last_truth.pose.yaw),
                          std::cos(believed.yaw - last_truth.pose.yaw))) *
      180.0 / M_PI;
  return summary;
}

}  // namespace rfm::sim
