// A scene as its YAML file spells it (degrees, metres, flow-style walls and people), and the
// writer that turns it into that file. Procedural scenes are built as descriptions, written out,
// and then loaded like any scene file, so what is simulated is exactly what was written. ROS-free.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "reflectance_field_map/sim/beam_physics.h"
#include "reflectance_field_map/sim/lidar.h"
#include "reflectance_field_map/sim/odometry.h"
#include "reflectance_field_map/sim/people.h"
#include "reflectance_field_map/sim/scan_logger.h"
#include "reflectance_field_map/sim/world.h"

namespace rfm::sim {

// One entry of the scene file's `walls` list.
struct WallDescription {
  enum class Type { kSegment, kPolyline, kArc };
  Type type = Type::kSegment;
  Material material = Material::kDiffuse;
  std::vector<Eigen::Vector2d> points;               // segment, polyline
  bool closed = false;                               // polyline
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // arc
  double radius = 0.0, start_deg = 0.0, end_deg = 0.0;
  double frame = 0.0;  // written always: the loader's default differs by material
  double mullion_spacing = 0.0;
  double dirt = 0.0;
  double tilt_deg = 0.0;
};

struct RobotDescription {
  double speed = 0.7;
  double turn_rate_deg = 45.0;
  double start_delay = 1.0;
  std::vector<Eigen::Vector2d> waypoints;
  std::vector<double> pauses;  // s waited on arrival at each waypoint (missing: none)
};

struct SceneDescription {
  std::string comment;  // written as '#' lines at the top
  std::string name;
  std::string description;
  double duration = 60.0;
  std::uint32_t seed = 1;
  std::optional<RealisticPhysics> physics;
  std::optional<OdometryDrift> odometry;
  ScanLoggerSpec logger;
  std::vector<LidarSpec> lidars;
  std::vector<WallDescription> walls;
  std::vector<PersonSpec> people;
  RobotDescription robot;
};

// The shortest decimal text that reads back as exactly `value`.
std::string formatNumber(double value);

// The scene file (config/scenes/README.md format) of `scene`.
std::string sceneToYaml(const SceneDescription& scene);

// Adds `wall` to `world` as the scene loader does.
void addWall(World& world, const WallDescription& wall);

}  // namespace rfm::sim
