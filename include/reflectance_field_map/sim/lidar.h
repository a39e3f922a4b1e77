// Sensor model of a 2D scanning lidar (defaults: Hokuyo UTM-30LX): beam geometry, range noise,
// random dropouts and the REP-117 encoding of missing echoes. ROS-free.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "reflectance_field_map/sim/beam_physics.h"
#include "reflectance_field_map/sim/trajectory.h"

namespace rfm::sim {

struct LidarSpec {
  std::string topic = "/scan_front";
  std::string frame_id = "laser_front";
  // Mount on base_link (the scan plane is horizontal; z only goes into the static TF).
  double mount_x = 0.35, mount_y = 0.0, mount_z = 0.3, mount_yaw = 0.0;
  int beam_count = 1081;
  double angle_min = -135.0 * M_PI / 180.0;
  double angle_increment = 0.25 * M_PI / 180.0;
  double range_min = 0.1;
  double range_max = 30.0;
  double rate_hz = 40.0;
  double time_offset = 0.0;  // first scan at scene time `time_offset`, then every 1 / rate_hz
  double range_noise_sigma = 0.012;
  double dropout_probability = 0.02;  // random missing echoes (dark spots, sensor misses)
  double range_noise_per_m = 0.0;     // the noise's standard deviation grows this much per metre
  // Read by the realistic sensor model only (scenes with a `physics` section): beams are taken one
  // after another as the mirror turns (REP-117 time_increment), so the robot and people move
  // during a scan; otherwise every beam is taken at the scan's stamp.
  bool sweep = false;
  double mirror_hz = 0.0;  // mirror revolutions per second (0: one per scan, rate_hz)
  double mount_pitch = 0.0, mount_roll = 0.0;  // static tilt of the scan plane, rad

  double angleMax() const { return angle_min + (beam_count - 1) * angle_increment; }
  // Time between two beams while sweeping (0 when the scan is taken at one instant).
  double timeIncrement() const;
  double beamAngle(int beam) const { return angle_min + beam * angle_increment; }
  Pose2 mount() const { return {mount_x, mount_y, mount_yaw}; }
  // Throws std::invalid_argument naming the offending parameter.
  void validate() const;
};

// Chassis pitch and roll (rad) at an instant.
struct Tilt {
  double pitch = 0.0, roll = 0.0;
};

// What moves while a scan is taken: the robot (its true pose and chassis tilt) and the people.
class MovingScene {
 public:
  virtual ~MovingScene() = default;
  virtual Pose2 robotPose(double t) const = 0;
  virtual Tilt chassisTilt(double t) const = 0;
  virtual std::vector<Circle> people(double t) const = 0;
};

// One simulated scan: what the sensor reports and the truth behind every beam.
struct SimScan {
  double time = 0.0;  // scene time of the scan (all beams are taken at this instant)
  std::size_t lidar_index = 0;
  std::vector<float> ranges;  // +inf = no echo within range_max, -inf = closer than range_min
  std::vector<std::uint8_t> classes;  // BeamClass per beam
};

class LidarSensor {
 public:
  explicit LidarSensor(LidarSpec spec);

  // Simulates a scan with the robot at `robot_pose`. `specular_window_rad` is the scan's tilt-
  // dependent glass/mirror return window (see MaterialModel).
  SimScan scan(const BeamTracer& tracer, const Pose2& robot_pose, double time,
               const std::vector<Circle>& people, double specular_window_rad,
               std::mt19937& rng) const;

  // Simulates a scan with the realistic sensor model: RealisticPhysics, tilt-dependent elevation of
  // every beam, range noise growing with range, and (with `sweep`) the robot and people moving
  // between beams. The scan's stamp is its first beam's time.
  SimScan scanRealistic(const BeamTracer& tracer, const MovingScene& motion, double time,
                        std::mt19937& rng) const;

  const LidarSpec& spec() const { return spec_; }

 private:
  LidarSpec spec_;
  std::vector<double> beam_cos_, beam_sin_;  // beam directions in the laser frame
};

}  // namespace rfm::sim
