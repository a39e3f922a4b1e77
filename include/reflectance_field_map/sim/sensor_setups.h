// Named sensor setups a scene or rfm_sim --setup can pick: one or two lidars of common kinds,
// and for sparse logs the logger that thins their scans. ROS-free.
#pragma once

#include <string>
#include <vector>

#include "reflectance_field_map/sim/lidar.h"
#include "reflectance_field_map/sim/scan_logger.h"

namespace rfm::sim {

struct SensorSetup {
  std::string name;
  std::string description;
  std::vector<LidarSpec> lidars;
  ScanLoggerSpec logger;  // off unless the setup is a thinned log
};

// Every setup, the default (the wheelchair's two UTM-30LX) first.
const std::vector<SensorSetup>& sensorSetups();
// The setup called `name`; throws std::invalid_argument listing the names otherwise.
const SensorSetup& sensorSetup(const std::string& name);

// The two Hokuyo UTM-30LX of the paper's wheelchair; the rear one fires half a period later.
std::vector<LidarSpec> defaultWheelchairLidars();

}  // namespace rfm::sim
