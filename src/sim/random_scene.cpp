#include "reflectance_field_map/sim/random_scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "reflectance_field_map/sim/crowd.h"
#include "reflectance_field_map/sim/floor_plan.h"
#include "reflectance_field_map/sim/navigation_grid.h"
#include "reflectance_field_map/sim/random_draws.h"
#include "reflectance_field_map/sim/sensor_setups.h"
#include "reflectance_field_map/sim/trajectory.h"

namespace rfm::sim {
namespace {

using Vec = Eigen::Vector2d;

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kGridResolution = 0.1;  // m

// Streams of draws, one per part of the scene.
enum Stream : std::uint32_t { kFloor = 1, kPhysics, kRobot, kPeople, kSensors, kOdometry };

// The glass, metal and sensor physics of one scene, within what the paper and real glass show.
RealisticPhysics drawPhysics(Dice& dice) {
  RealisticPhysics p;
  p.enabled = true;
  p.return_cone_deg = rounded(dice.uniform(1.5, 4.0), 100);
  p.bump_tilt_deg = rounded(dice.uniform(0.2, 1.2), 100);
  p.bump_correlation_s = rounded(dice.uniform(0.08, 0.3), 1000);
  p.standing_tilt_deg = rounded(dice.uniform(0.0, 0.1), 1000);
  p.refractive_index = rounded(dice.uniform(1.45, 1.6), 1000);
  p.empty_echo_probability = rounded(dice.uniform(0.05, 0.4), 1000);
  p.empty_echo_decay_deg = rounded(dice.uniform(8.0, 30.0), 10);
  p.metal_lobe_deg = rounded(dice.uniform(8.0, 15.0), 10);
  p.metal_tail_probability = rounded(dice.uniform(0.02, 0.2), 1000);
  p.metal_tail_decay_deg = rounded(dice.uniform(3.0, 15.0), 10);
  p.diffuse_max_incidence_deg = rounded(dice.uniform(80.0, 89.0), 10);
  p.grazing_dropout = rounded(dice.uniform(0.02, 0.25), 1000);
  p.range_dropout = rounded(dice.uniform(0.0, 0.3), 1000);
  p.gloss_probability = rounded(dice.uniform(0.0, 0.15), 1000);
  p.max_interactions = 4;
  return p;
}

// Odometry with every error at zero: poses corrected by a localiser, as in CARMEN's corrected
// logs. The scene still has its odometry, so that its bag holds map -> odom like the others.
OdometryDrift perfectOdometry() {
  OdometryDrift drift;
  drift.enabled = true;
  drift.xy_noise = drift.yaw_noise_deg = drift.turn_noise_deg = 0.0;
  drift.scale_error = drift.turn_scale_error = drift.yaw_bias_deg_per_m = 0.0;
  return drift;
}

// Wheel odometry of the wheelchair's quality, scaled down at random; a quarter of the scenes
// have perfect odometry.
OdometryDrift drawOdometry(Dice& dice) {
  if (dice.chance(0.25)) return perfectOdometry();
  const double quality = dice.uniform(0.25, 1.0);
  auto sign = [&] { return dice.chance(0.5) ? 1.0 : -1.0; };
  OdometryDrift drift;
  drift.enabled = true;
  drift.xy_noise = rounded(quality * drift.xy_noise, 10000);
  drift.yaw_noise_deg = rounded(quality * drift.yaw_noise_deg, 1000);
  drift.turn_noise_deg = rounded(quality * drift.turn_noise_deg, 1000);
  drift.scale_error = rounded(sign() * quality * dice.uniform(0.0, 1.0) * drift.scale_error, 10000);
  drift.turn_scale_error =
      rounded(sign() * quality * dice.uniform(0.0, 1.0) * drift.turn_scale_error, 10000);
  drift.yaw_bias_deg_per_m =
      rounded(sign() * quality * dice.uniform(0.0, 1.0) * drift.yaw_bias_deg_per_m, 10000);
  return drift;
}

// The setup's lidars as real units vary: mounts a little off level, noise a little off the data
// sheet, and every scan swept beam by beam.
std::vector<LidarSpec> drawLidars(Dice& dice, const SensorSetup& setup) {
  std::vector<LidarSpec> lidars = setup.lidars;
  for (LidarSpec& lidar : lidars) {
    lidar.sweep = true;
    lidar.mount_pitch = rounded(std::clamp(dice.normal(0.0, 0.3), -1.0, 1.0), 100) * kDegToRad;
    lidar.mount_roll = rounded(std::clamp(dice.normal(0.0, 0.3), -1.0, 1.0), 100) * kDegToRad;
    lidar.range_noise_sigma = rounded(lidar.range_noise_sigma * dice.uniform(0.8, 1.3), 10000);
    lidar.range_noise_per_m = rounded(lidar.range_noise_per_m * dice.uniform(0.8, 1.3), 100000);
    // Random misses on a plain wall in range are rare; the physics loses the faint returns
    // (grazing, far, dark) on top.
    lidar.dropout_probability = rounded(lidar.dropout_probability * dice.uniform(0.05, 0.5), 10000);
  }
  return lidars;
}

TrajectorySpec trajectoryOf(const RobotDescription& robot) {
  TrajectorySpec spec;
  spec.speed = robot.speed;
  spec.turn_rate = robot.turn_rate_deg * kDegToRad;
  spec.start_delay = robot.start_delay;
  spec.waypoints = robot.waypoints;
  spec.pauses = robot.pauses;
  return spec;
}

bool inside(const FloorPlan& plan, const Vec& p) {
  return (p.array() > plan.building_low.array()).all() &&
         (p.array() < plan.building_high.array()).all();
}

// A wheelchair's drive from room to room until the scene's time is used up.
class DrivePlanner {
 public:
  DrivePlanner(Dice& dice, const FloorPlan& plan, const NavigationGrid& grid)
      : dice_(dice), plan_(plan), grid_(grid) {
    for (const FloorPlanArea& area : plan.areas)
      if (!area.outside) rooms_.push_back(area);
  }

  RobotDescription plan(double duration) {
    RobotDescription robot;
    robot.speed = rounded(dice_.uniform(0.4, 1.0), 100);
    robot.turn_rate_deg = rounded(dice_.uniform(25.0, 60.0), 10);
    robot.start_delay = rounded(dice_.uniform(0.5, 2.0), 10);
    // A start in a room shut off from the rest (a door too narrow) leads nowhere: start elsewhere.
    for (int attempt = 0; attempt < 10 && robot.waypoints.size() < 2; ++attempt) {
      robot.waypoints.clear();
      robot.pauses.clear();
      std::optional<Vec> start;
      for (int tries = 0; tries < 50 && !start; ++tries)
        start = cellIn(dice_.pick(rooms_));
      if (!start) throw std::runtime_error("random scene: no room for the robot");
      robot.waypoints.push_back(*start);
      drive(robot, duration);
    }
    if (robot.waypoints.size() < 2) throw std::runtime_error("random scene: no path for the robot");
    return robot;
  }

 private:
  // Half the wheelchair's width (its lidars sit on its axis) plus a margin, m.
  static constexpr double kClearance = 0.45;

  std::optional<Vec> cellIn(const FloorPlanArea& area) {
    const std::vector<Vec> cells = grid_.freeCells(area.low, area.high, kClearance);
    if (cells.empty()) return std::nullopt;
    const Vec& cell = dice_.pick(cells);
    return Vec(rounded(cell.x(), 100), rounded(cell.y(), 100));
  }

  // Appends goals, reached by the shortest clear route inside the building, until `duration`.
  void drive(RobotDescription& robot, double duration) {
    auto insideOnly = [&](const Vec& p) { return inside(plan_, p); };
    double time = robot.start_delay;
    double heading = 0.0;
    bool has_heading = false;
    for (int attempt = 0; attempt < 200 && time < duration; ++attempt) {
      const auto goal = cellIn(dice_.pick(rooms_));
      if (!goal || (*goal - robot.waypoints.back()).norm() < 2.0) continue;
      const auto path = grid_.path(robot.waypoints.back(), *goal, kClearance, insideOnly);
      if (!path) continue;
      for (std::size_t i = 1; i < path->size(); ++i) {
        const Vec point(rounded((*path)[i].x(), 100), rounded((*path)[i].y(), 100));
        const Vec leg = point - robot.waypoints.back();
        if (leg.norm() < 0.05) continue;
        const double direction = std::atan2(leg.y(), leg.x());
        if (has_heading) {
          time += std::abs(std::remainder(direction - heading, 2.0 * M_PI)) /
                  (robot.turn_rate_deg * kDegToRad);
        }
        heading = direction;
        has_heading = true;
        time += leg.norm() / robot.speed;
        robot.waypoints.push_back(point);
      }
      if (dice_.chance(0.3)) {  // waits at its goal: a door, a lift, someone in the way
        robot.pauses.resize(robot.waypoints.size(), 0.0);
        robot.pauses.back() = rounded(dice_.uniform(2.0, 10.0), 10);
        time += robot.pauses.back();
      }
    }
  }

  Dice& dice_;
  const FloorPlan& plan_;
  const NavigationGrid& grid_;
  std::vector<FloorPlanArea> rooms_;
};

}  // namespace

RandomScene generateRandomScene(const RandomSceneOptions& options) {
  const SensorSetup& setup = sensorSetup(options.setup);
  const std::uint32_t seed = options.seed;
  Dice floor(seed, kFloor), physics(seed, kPhysics), robot_dice(seed, kRobot),
      people(seed, kPeople), sensors(seed, kSensors), odometry(seed, kOdometry);

  SceneDescription scene;
  scene.duration =
      options.duration ? *options.duration : rounded(robot_dice.uniform(40.0, 80.0), 1);
  if (!(scene.duration >= 5.0 && scene.duration <= 3600.0)) {
    throw std::invalid_argument("a random scene's duration must be in [5, 3600] s");
  }
  const FloorPlan plan = generateFloorPlan(floor);
  scene.walls = plan.walls;
  World world;
  for (const WallDescription& wall : scene.walls)
    addWall(world, wall);
  const NavigationGrid grid(world, plan.world_low - Vec::Constant(1.0),
                            plan.world_high + Vec::Constant(1.0), kGridResolution);

  scene.robot = DrivePlanner(robot_dice, plan, grid).plan(scene.duration);
  const RobotTrajectory trajectory(trajectoryOf(scene.robot), scene.duration);
  scene.people = generateCrowd(people, {world, grid, plan, trajectory, scene.duration});

  scene.physics = drawPhysics(physics);
  scene.lidars = drawLidars(sensors, setup);
  scene.logger = options.logger ? *options.logger : setup.logger;
  const OdometryDrift drift = drawOdometry(odometry);
  scene.odometry = options.odometry_drift ? drift : perfectOdometry();

  scene.seed = seed;
  scene.name = "random_" + std::to_string(seed);
  scene.description =
      plan.summary + "; " + std::to_string(scene.people.size()) + " people; setup " + setup.name;
  scene.comment = "Procedural scene: rfm_sim --random " + std::to_string(seed) + " --setup " +
                  setup.name + ".\nSimulate this file to reproduce it exactly: rfm_sim --scene " +
                  "THIS.yaml --out OUT.bag";
  RandomScene result;
  result.yaml = sceneToYaml(scene);
  result.description = std::move(scene);
  return result;
}

}  // namespace rfm::sim
