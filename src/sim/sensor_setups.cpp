#include "reflectance_field_map/sim/sensor_setups.h"

#include <cmath>
#include <stdexcept>

namespace rfm::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// A single lidar on /scan at the front of the robot: `beam_count` beams `step_deg` apart from
// `first_deg`.
LidarSpec singleLidar(double first_deg, double step_deg, int beam_count, double rate_hz,
                      double range_max) {
  LidarSpec lidar;
  lidar.topic = "/scan";
  lidar.frame_id = "laser";
  lidar.mount_x = 0.35;
  lidar.beam_count = beam_count;
  lidar.angle_min = first_deg * kDegToRad;
  lidar.angle_increment = step_deg * kDegToRad;
  lidar.rate_hz = rate_hz;
  lidar.range_max = range_max;
  return lidar;
}

std::vector<SensorSetup> buildSetups() {
  std::vector<SensorSetup> setups;
  setups.push_back({"wheelchair",
                    "two Hokuyo UTM-30LX, front and rear: 270 deg, 0.25 deg, 40 Hz, 30 m (default)",
                    defaultWheelchairLidars(),
                    {}});

  LidarSpec utm = defaultWheelchairLidars().front();
  utm.topic = "/scan";
  utm.frame_id = "laser";
  setups.push_back(
      {"utm30", "one Hokuyo UTM-30LX in front: 270 deg, 0.25 deg, 40 Hz, 30 m", {utm}, {}});

  // SICK LMS200-class: the mirror turns at 75 Hz, the serial line carries 5 scans a second.
  LidarSpec sick = singleLidar(-90.0, 1.0, 181, 5.0, 80.0);
  sick.range_noise_sigma = 0.008;
  sick.range_noise_per_m = 0.0002;
  sick.dropout_probability = 0.01;
  sick.mirror_hz = 75.0;
  setups.push_back({"sick180", "one SICK LMS-class lidar: 180 deg, 1 deg, 5 Hz, 80 m", {sick}, {}});

  // A full turn: the last beam stops one step short of the first.
  LidarSpec ring = singleLidar(-180.0, 0.5, 720, 10.0, 30.0);
  ring.mount_x = 0.0;
  ring.mount_z = 0.4;
  ring.range_noise_sigma = 0.015;
  ring.range_noise_per_m = 0.001;
  ring.dropout_probability = 0.03;
  setups.push_back({"ring360", "one spinning 360 deg lidar: 0.5 deg, 10 Hz, 30 m", {ring}, {}});

  // Hokuyo URG-04LX-class, 180 of its 240 deg: 1024 steps a turn, 10 Hz, 5.6 m, 1 % noise.
  LidarSpec urg = singleLidar(-90.0, 360.0 / 1024.0, 512, 10.0, 5.6);
  urg.range_min = 0.02;
  urg.range_noise_sigma = 0.005;
  urg.range_noise_per_m = 0.005;
  urg.dropout_probability = 0.03;
  setups.push_back({"urg_short",
                    "one short-range Hokuyo URG-class lidar: 180 deg, 0.35 deg, 10 Hz, 5.6 m",
                    {urg},
                    {}});

  // A CARMEN corrected log: a SICK at 0.5 deg whose logger kept a scan every metre or 30 deg of
  // travel, as in the Radish logs of ../shared/data (median spacing 0.5-1 m there).
  LidarSpec carmen = singleLidar(-90.0, 0.5, 361, 5.0, 80.0);
  carmen.range_noise_sigma = 0.008;
  carmen.range_noise_per_m = 0.0002;
  carmen.dropout_probability = 0.01;
  carmen.mirror_hz = 75.0;
  ScanLoggerSpec sparse;
  sparse.keep_every_m = 1.0;
  sparse.keep_every_deg = 30.0;
  setups.push_back(
      {"carmen_sparse",
       "a CARMEN corrected log: SICK 180 deg, 0.5 deg, 5 Hz, 80 m, a scan kept every 1 m or "
       "30 deg",
       {carmen},
       sparse});
  return setups;
}

}  // namespace

std::vector<LidarSpec> defaultWheelchairLidars() {
  LidarSpec front;
  front.topic = "/scan_front";
  front.frame_id = "laser_front";
  front.mount_x = 0.35;
  front.mount_yaw = 0.0;
  LidarSpec rear = front;
  rear.topic = "/scan_rear";
  rear.frame_id = "laser_rear";
  rear.mount_x = -0.35;
  rear.mount_yaw = M_PI;
  rear.time_offset = 0.5 / rear.rate_hz;
  return {front, rear};
}

const std::vector<SensorSetup>& sensorSetups() {
  static const std::vector<SensorSetup> setups = buildSetups();
  return setups;
}

const SensorSetup& sensorSetup(const std::string& name) {
  std::string names;
  for (const SensorSetup& setup : sensorSetups()) {
    if (setup.name == name) return setup;
    names += (names.empty() ? "" : ", ") + setup.name;
  }
  throw std::invalid_argument("unknown sensor setup '" + name + "' (expected one of: " + names +
                              ")");
}

}  // namespace rfm::sim
