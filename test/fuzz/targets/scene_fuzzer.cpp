// A scene file as rfm_sim reads it: rfm::sim::parseScene, which either refuses the scene with a
// SceneError or returns one that can be simulated. An accepted scene is then run for its first
// tenth of a second with few beams, so that what parsing lets through (walls, people, the
// robot's route) reaches the simulator too.
#include "reflectance_field_map/sim/scene.h"
#include "reflectance_field_map/sim/simulator.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

namespace {

class DiscardingSink : public rfm::sim::SimulationSink {
 public:
  void onRobotState(double, const rfm::sim::RobotState&, const rfm::sim::Pose2&) override {}
  void onScan(const rfm::sim::SimScan&, const rfm::sim::LidarSpec&) override {}
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  rfm::sim::Scene scene;
  try {
    scene = rfm::sim::parseScene(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const rfm::sim::SceneError&) {
    return 0;
  }
  scene.duration = std::min(scene.duration, 0.1);
  for (rfm::sim::LidarSpec& lidar : scene.lidars)
    lidar.beam_count = std::min(lidar.beam_count, 32);
  rfm::sim::Simulator simulator(scene, scene.seed);
  DiscardingSink sink;
  simulator.run(sink);
  return 0;
}
