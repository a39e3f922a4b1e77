#include "reflectance_field_map/sim/simulator.h"

#include <cmath>
#include <limits>

namespace rfm::sim {

Simulator::Simulator(const Scene& scene, std::uint32_t seed)
    : scene_(scene),
      trajectory_(scene.robot, scene.duration),
      tracer_(scene.world, scene.materials),
      seed_(seed) {
  scene_.materials.validate();
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
      sink.onRobotState(best_time, trajectory_.stateAt(best_time));
      ++summary.robot_states;
      ++next_state;
      continue;
    }
    const std::size_t lidar = static_cast<std::size_t>(best_lidar);
    std::mt19937& rng = lidar_rngs[lidar];
    // The return window of glass and mirrors varies per scan with out-of-plane tilt.
    const double window = std::uniform_real_distribution<double>(window_min, window_max)(rng);
    SimScan scan = lidars_[lidar].scan(tracer_, trajectory_.stateAt(best_time).pose, best_time,
                                       peopleAt(people_, best_time), window, rng);
    scan.lidar_index = lidar;
    for (const std::uint8_t beam_class : scan.classes)
      ++summary.beams_per_class[beam_class];
    sink.onScan(scan, lidars_[lidar].spec());
    ++summary.scans;
    ++next_scan[lidar];
  }
  return summary;
}

}  // namespace rfm::sim
