// A simulation scene (walls, people, robot path, sensors) and its YAML loader. The file format is
// documented in config/scenes/README.md. ROS-free.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "reflectance_field_map/sim/beam_physics.h"
#include "reflectance_field_map/sim/lidar.h"
#include "reflectance_field_map/sim/odometry.h"
#include "reflectance_field_map/sim/people.h"
#include "reflectance_field_map/sim/scan_logger.h"
#include "reflectance_field_map/sim/sensor_setups.h"
#include "reflectance_field_map/sim/trajectory.h"
#include "reflectance_field_map/sim/world.h"

namespace rfm::sim {

struct Scene {
  std::string name;
  std::string description;
  double duration = 60.0;  // seconds of data
  std::uint32_t seed = 1;
  World world;
  MaterialModel materials;
  RealisticPhysics physics;  // off unless the scene has a `physics` section
  std::vector<PersonSpec> people;
  TrajectorySpec robot;
  std::vector<LidarSpec> lidars;  // default: the wheelchair's front and rear UTM-30LX
  OdometryDrift odometry;         // off unless the scene has an `odometry` section
  ScanLoggerSpec logger;          // keeps every scan unless the scene or its setup thins them
  double tf_rate_hz = 100.0;
  double odom_rate_hz = 50.0;
};

// Error in a scene file. what() names the source and the offending field, e.g.
// "atrium.yaml: walls[2].material: unknown material 'glas' (...)"; field() is "walls[2].material".
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& source, const std::string& field, const std::string& message)
      : std::runtime_error(source + ": " + (field.empty() ? "" : field + ": ") + message),
        field_(field) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// Parses and validates a scene. `source` prefixes error messages (usually the file name).
Scene parseScene(const std::string& yaml_text, const std::string& source = "scene");
// Reads and parses a scene file; throws SceneError if unreadable or invalid.
Scene loadScene(const std::string& path);

}  // namespace rfm::sim
