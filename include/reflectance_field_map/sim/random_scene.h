// rfm_sim --random SEED: a whole scene drawn from a seed (floor plan, people, robot path, the
// physics of its glass, metal and sensors, and odometry drift), returned as its scene file.
// ROS-free.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "reflectance_field_map/sim/scan_logger.h"
#include "reflectance_field_map/sim/scene_description.h"

namespace rfm::sim {

struct RandomSceneOptions {
  std::uint32_t seed = 1;
  std::string setup = "wheelchair";      // a sensorSetups() name
  std::optional<double> duration;        // default: drawn in [40, 80] s
  std::optional<ScanLoggerSpec> logger;  // default: the setup's
  bool odometry_drift = true;            // false: odometry is the true path
};

struct RandomScene {
  SceneDescription description;
  std::string yaml;  // the scene file; simulate what parseScene() makes of it
};

// Throws std::invalid_argument for an unknown setup or a duration outside [5, 3600] s.
RandomScene generateRandomScene(const RandomSceneOptions& options);

}  // namespace rfm::sim
