// YAML scene loader: strict (unknown keys are errors) so that typos in a scene do not silently
// change the experiment. Every error names the offending field.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "reflectance_field_map/sim/scene.h"

namespace rfm::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
// Bounds that keep a scene's cost finite: a scene is a building, its points within this many
// metres of the origin (the walk checks and the simulation step along every path).
constexpr double kMaxCoordinate = 1000.0;
// Panes narrower than this are no window; closer mullions would only multiply surfaces.
constexpr double kMinMullionSpacing = 0.1;
// Every simulated ray is tested against every surface: more than this makes rfm_sim crawl.
constexpr std::size_t kMaxSurfaces = 2000;

class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw SceneError(source_, field, message);
  }

  void requireMap(const YAML::Node& node, const std::string& field) const {
    if (!node.IsMap()) fail(field, "expected a mapping");
  }

  void rejectUnknownKeys(const YAML::Node& node, const std::string& field,
                         const std::set<std::string>& allowed) const {
    for (const auto& entry : node) {
      const std::string key = entry.first.as<std::string>();
      if (!allowed.count(key)) {
        std::string expected;
        for (const std::string& name : allowed)
          expected += (expected.empty() ? "" : ", ") + name;
        fail(join(field, key), "unknown key (expected one of: " + expected + ")");
      }
    }
  }

  static std::string join(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
  }
  static std::string index(const std::string& parent, std::size_t i) {
    return parent + "[" + std::to_string(i) + "]";
  }

  double number(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(field, "expected a number");
    double value = 0.0;
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(field, "expected a number, got '" + node.Scalar() + "'");
    }
    if (!std::isfinite(value)) fail(field, "must be finite");
    return value;
  }

  double number(const YAML::Node& parent, const std::string& parent_field, const std::string& key,
                double fallback, double low, double high) const {
    const YAML::Node node = parent[key];
    if (!node) return fallback;
    const std::string field = join(parent_field, key);
    const double value = number(node, field);
    if (value < low || value > high) {
      std::ostringstream message;
      message << "must be in [" << low << ", " << high << "], got " << value;
      fail(field, message.str());
    }
    return value;
  }

  double requiredNumber(const YAML::Node& parent, const std::string& parent_field,
                        const std::string& key, double low, double high) const {
    if (!parent[key]) fail(join(parent_field, key), "missing (required)");
    return number(parent, parent_field, key, 0.0, low, high);
  }

  bool boolean(const YAML::Node& parent, const std::string& parent_field, const std::string& key,
               bool fallback) const {
    const YAML::Node node = parent[key];
    if (!node) return fallback;
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
      fail(join(parent_field, key), "expected true or false");
    }
  }

  std::string text(const YAML::Node& parent, const std::string& parent_field,
                   const std::string& key, const std::string& fallback) const {
    const YAML::Node node = parent[key];
    if (!node) return fallback;
    if (!node.IsScalar()) fail(join(parent_field, key), "expected a string");
    return node.Scalar();
  }

  double coordinate(const YAML::Node& node, const std::string& field) const {
    const double value = number(node, field);
    if (std::abs(value) > kMaxCoordinate) {
      std::ostringstream message;
      message << "must be within " << kMaxCoordinate << " m of the origin, got " << value;
      fail(field, message.str());
    }
    return value;
  }

  Eigen::Vector2d point(const YAML::Node& node, const std::string& field,
                        double* third = nullptr) const {
    const std::size_t max_size = third ? 3 : 2;
    if (!node.IsSequence() || node.size() < 2 || node.size() > max_size) {
      fail(field, third ? "expected [x, y] or [x, y, pause_s]" : "expected [x, y]");
    }
    if (third) *third = node.size() == 3 ? number(node[2], index(field, 2)) : 0.0;
    return {coordinate(node[0], index(field, 0)), coordinate(node[1], index(field, 1))};
  }

  // mullion_spacing: 0 (none), or panes at least kMinMullionSpacing wide and wider than the
  // mullions between them (as wide as the frame).
  double mullionSpacing(const YAML::Node& wall, const std::string& wall_field, double frame) const {
    const double spacing = number(wall, wall_field, "mullion_spacing", 0.0, 0.0, 1000.0);
    const double least = std::max(kMinMullionSpacing, 2.0 * frame);
    if (spacing > 0.0 && spacing < least) {
      std::ostringstream message;
      message << "must be 0 (no mullions) or at least " << least
              << " m (0.1 m, and twice the frame), got " << spacing;
      fail(join(wall_field, "mullion_spacing"), message.str());
    }
    return spacing;
  }

  // Refuses a wall of `length` m that would take the scene past kMaxSurfaces (a shiny wall has
  // a frame at each end, a mullion and a pane per spacing; a diffuse one is a single surface).
  void checkSurfaceCount(const World& world, double length, Material material,
                         double mullion_spacing, const std::string& wall_field) const {
    const bool framed = material != Material::kDiffuse;
    const double panes =
        framed && mullion_spacing > 0.0 ? std::round(length / mullion_spacing) : 1.0;
    const double surfaces = static_cast<double>(world.surfaceCount()) + 2.0 * panes + 3.0;
    if (surfaces <= static_cast<double>(kMaxSurfaces)) return;
    std::ostringstream message;
    message << "this wall takes the scene to about " << surfaces << " surfaces (at most "
            << kMaxSurfaces << "): fewer or wider panes";
    fail(join(wall_field, mullion_spacing > 0.0 ? "mullion_spacing" : "points"), message.str());
  }

  std::vector<Eigen::Vector2d> points(const YAML::Node& parent, const std::string& parent_field,
                                      const std::string& key, std::size_t min_count) const {
    const std::string field = join(parent_field, key);
    const YAML::Node node = parent[key];
    if (!node) fail(field, "missing (required)");
    if (!node.IsSequence()) fail(field, "expected a list of [x, y] points");
    if (node.size() < min_count) {
      fail(field, "needs at least " + std::to_string(min_count) + " points");
    }
    std::vector<Eigen::Vector2d> result;
    for (std::size_t i = 0; i < node.size(); ++i)
      result.push_back(point(node[i], index(field, i)));
    return result;
  }

  Material material(const YAML::Node& parent, const std::string& parent_field) const {
    const std::string field = join(parent_field, "material");
    if (!parent["material"]) fail(field, "missing (required)");
    const std::string name = text(parent, parent_field, "material", "");
    if (name == "diffuse") return Material::kDiffuse;
    if (name == "glass") return Material::kGlass;
    if (name == "mirror") return Material::kMirror;
    if (name == "metal") return Material::kMetal;
    fail(field, "unknown material '" + name + "' (expected diffuse, glass, mirror or metal)");
  }

  void walls(const YAML::Node& node, World& world) const {
    const std::string field = "walls";
    if (!node) fail(field, "missing (required)");
    if (!node.IsSequence() || node.size() == 0) fail(field, "expected a non-empty list of walls");
    for (std::size_t i = 0; i < node.size(); ++i) {
      const YAML::Node wall = node[i];
      const std::string wall_field = index(field, i);
      requireMap(wall, wall_field);
      const std::string type = text(wall, wall_field, "type", "");
      const Material wall_material = material(wall, wall_field);
      const double default_frame = wall_material == Material::kDiffuse ? 0.0 : 0.05;
      const double frame = number(wall, wall_field, "frame", default_frame, 0.0, 1.0);
      const double mullions = mullionSpacing(wall, wall_field, frame);
      SurfaceFinish finish;
      finish.dirt = number(wall, wall_field, "dirt", 0.0, 0.0, 1.0);
      finish.tilt = number(wall, wall_field, "tilt_deg", 0.0, -5.0, 5.0) * kDegToRad;
      if (type == "segment" || type == "polyline") {
        rejectUnknownKeys(wall, wall_field,
                          {"type", "material", "points", "frame", "mullion_spacing", "closed",
                           "dirt", "tilt_deg"});
        std::vector<Eigen::Vector2d> corners = points(wall, wall_field, "points", 2);
        if (type == "segment" && corners.size() != 2) {
          fail(join(wall_field, "points"), "a segment has exactly 2 points");
        }
        if (boolean(wall, wall_field, "closed", false)) corners.push_back(corners.front());
        for (std::size_t k = 0; k + 1 < corners.size(); ++k) {
          if ((corners[k + 1] - corners[k]).norm() < 1e-6) {
            fail(index(join(wall_field, "points"), k + 1), "repeats the previous point");
          }
          checkSurfaceCount(world, (corners[k + 1] - corners[k]).norm(), wall_material, mullions,
                            wall_field);
          world.addFramedSegment(corners[k], corners[k + 1], wall_material, frame, mullions,
                                 finish);
        }
      } else if (type == "arc") {
        rejectUnknownKeys(wall, wall_field,
                          {"type", "material", "center", "radius", "start_deg", "end_deg", "frame",
                           "mullion_spacing", "dirt", "tilt_deg"});
        if (!wall["center"]) fail(join(wall_field, "center"), "missing (required)");
        const Eigen::Vector2d center = point(wall["center"], join(wall_field, "center"));
        const double radius = requiredNumber(wall, wall_field, "radius", 0.01, 1000.0);
        const double start = requiredNumber(wall, wall_field, "start_deg", -720.0, 720.0);
        const double end = requiredNumber(wall, wall_field, "end_deg", -720.0, 720.0);
        if (end <= start || end - start > 360.0) {
          fail(join(wall_field, "end_deg"), "must satisfy start_deg < end_deg <= start_deg + 360");
        }
        checkSurfaceCount(world, radius * (end - start) * kDegToRad, wall_material, mullions,
                          wall_field);
        world.addFramedArc(center, radius, start * kDegToRad, end * kDegToRad, wall_material, frame,
                           mullions, finish);
      } else {
        fail(join(wall_field, "type"),
             "unknown wall type '" + type + "' (expected segment, polyline or arc)");
      }
    }
  }

  MaterialModel materials(const YAML::Node& node) const {
    MaterialModel model;
    if (!node) return model;
    const std::string field = "materials";
    requireMap(node, field);
    rejectUnknownKeys(
        node, field,
        {"specular_window_deg", "glass_reflect_probability", "metal_lobe_deg",
         "metal_scatter_probability", "diffuse_max_incidence_deg", "max_interactions"});
    if (const YAML::Node window = node["specular_window_deg"]) {
      const std::string window_field = join(field, "specular_window_deg");
      if (!window.IsSequence() || window.size() != 2) fail(window_field, "expected [min, max]");
      model.specular_window_min_deg = number(window[0], index(window_field, 0));
      model.specular_window_max_deg = number(window[1], index(window_field, 1));
      if (model.specular_window_min_deg < 0.0 ||
          model.specular_window_max_deg < model.specular_window_min_deg ||
          model.specular_window_max_deg > 45.0) {
        fail(window_field, "need 0 <= min <= max <= 45");
      }
    }
    model.glass_reflect_probability =
        number(node, field, "glass_reflect_probability", model.glass_reflect_probability, 0.0, 1.0);
    model.metal_lobe_deg = number(node, field, "metal_lobe_deg", model.metal_lobe_deg, 0.0, 90.0);
    model.metal_scatter_probability =
        number(node, field, "metal_scatter_probability", model.metal_scatter_probability, 0.0, 1.0);
    model.diffuse_max_incidence_deg = number(node, field, "diffuse_max_incidence_deg",
                                             model.diffuse_max_incidence_deg, 0.0, 90.0);
    model.max_interactions = static_cast<int>(
        number(node, field, "max_interactions", model.max_interactions, 0.0, 32.0));
    return model;
  }

  RealisticPhysics physics(const YAML::Node& node) const {
    RealisticPhysics model;
    if (!node) return model;
    const std::string field = "physics";
    requireMap(node, field);
    rejectUnknownKeys(
        node, field,
        {"return_cone_deg", "bump_tilt_deg", "bump_correlation_s", "standing_tilt_deg",
         "refractive_index", "empty_echo_probability", "empty_echo_decay_deg", "metal_lobe_deg",
         "metal_tail_probability", "metal_tail_decay_deg", "diffuse_max_incidence_deg",
         "grazing_dropout", "range_dropout", "gloss_probability", "max_interactions"});
    model.enabled = true;
    auto read = [&](const char* key, double& value, double low, double high) {
      value = number(node, field, key, value, low, high);
    };
    read("return_cone_deg", model.return_cone_deg, 0.0, 45.0);
    read("bump_tilt_deg", model.bump_tilt_deg, 0.0, 10.0);
    read("bump_correlation_s", model.bump_correlation_s, 0.001, 10.0);
    read("standing_tilt_deg", model.standing_tilt_deg, 0.0, 10.0);
    read("refractive_index", model.refractive_index, 1.0, 3.0);
    read("empty_echo_probability", model.empty_echo_probability, 0.0, 1.0);
    read("empty_echo_decay_deg", model.empty_echo_decay_deg, 0.1, 90.0);
    read("metal_lobe_deg", model.metal_lobe_deg, 0.0, 90.0);
    read("metal_tail_probability", model.metal_tail_probability, 0.0, 1.0);
    read("metal_tail_decay_deg", model.metal_tail_decay_deg, 0.1, 90.0);
    read("diffuse_max_incidence_deg", model.diffuse_max_incidence_deg, 0.0, 90.0);
    read("grazing_dropout", model.grazing_dropout, 0.0, 1.0);
    read("range_dropout", model.range_dropout, 0.0, 1.0);
    read("gloss_probability", model.gloss_probability, 0.0, 1.0);
    model.max_interactions = static_cast<int>(
        number(node, field, "max_interactions", model.max_interactions, 0.0, 32.0));
    return model;
  }

  OdometryDrift odometry(const YAML::Node& node) const {
    OdometryDrift drift;
    if (!node) return drift;
    const std::string field = "odometry";
    if (node.IsNull()) {  // `odometry:` alone: the default wheelchair drift
      drift.enabled = true;
      return drift;
    }
    requireMap(node, field);
    rejectUnknownKeys(node, field,
                      {"xy_noise", "yaw_noise_deg", "turn_noise_deg", "scale_error",
                       "turn_scale_error", "yaw_bias_deg_per_m"});
    drift.enabled = true;
    drift.xy_noise = number(node, field, "xy_noise", drift.xy_noise, 0.0, 1.0);
    drift.yaw_noise_deg = number(node, field, "yaw_noise_deg", drift.yaw_noise_deg, 0.0, 10.0);
    drift.turn_noise_deg = number(node, field, "turn_noise_deg", drift.turn_noise_deg, 0.0, 10.0);
    drift.scale_error = number(node, field, "scale_error", drift.scale_error, -0.2, 0.2);
    drift.turn_scale_error =
        number(node, field, "turn_scale_error", drift.turn_scale_error, -0.2, 0.2);
    drift.yaw_bias_deg_per_m =
        number(node, field, "yaw_bias_deg_per_m", drift.yaw_bias_deg_per_m, -5.0, 5.0);
    return drift;
  }

  ScanLoggerSpec logger(const YAML::Node& node) const {
    const std::string field = "logger";
    requireMap(node, field);
    rejectUnknownKeys(node, field, {"keep_every_m", "keep_every_deg"});
    ScanLoggerSpec spec;
    spec.keep_every_m = number(node, field, "keep_every_m", 0.0, 0.0, 100.0);
    spec.keep_every_deg = number(node, field, "keep_every_deg", 0.0, 0.0, 360.0);
    return spec;
  }

  std::vector<LidarSpec> lidars(const YAML::Node& node) const {
    const std::string field = "lidars";
    if (!node.IsSequence() || node.size() == 0 || node.size() > 8) {
      fail(field, "expected a list of 1 to 8 lidars");
    }
    std::vector<LidarSpec> result;
    std::set<std::string> topics, frames;
    for (std::size_t i = 0; i < node.size(); ++i) {
      const YAML::Node entry = node[i];
      const std::string lidar_field = index(field, i);
      requireMap(entry, lidar_field);
      rejectUnknownKeys(entry, lidar_field,
                        {"topic", "frame_id", "mount", "beam_count", "angle_min_deg",
                         "angle_increment_deg", "range_min", "range_max", "rate_hz", "time_offset",
                         "range_noise_sigma", "range_noise_per_m", "dropout_probability", "sweep",
                         "mirror_hz", "mount_pitch_deg", "mount_roll_deg"});
      LidarSpec lidar;
      lidar.topic = text(entry, lidar_field, "topic", "");
      lidar.frame_id = text(entry, lidar_field, "frame_id", "");
      if (lidar.topic.empty() || lidar.topic[0] != '/') {
        fail(join(lidar_field, "topic"), "required, an absolute topic name such as /scan");
      }
      if (lidar.frame_id.empty()) fail(join(lidar_field, "frame_id"), "missing (required)");
      if (!topics.insert(lidar.topic).second) fail(join(lidar_field, "topic"), "used twice");
      if (!frames.insert(lidar.frame_id).second) fail(join(lidar_field, "frame_id"), "used twice");
      if (const YAML::Node mount = entry["mount"]) {
        const std::string mount_field = join(lidar_field, "mount");
        if (!mount.IsSequence() || mount.size() != 4)
          fail(mount_field, "expected [x, y, z, yaw_deg]");
        lidar.mount_x = number(mount[0], index(mount_field, 0));
        lidar.mount_y = number(mount[1], index(mount_field, 1));
        lidar.mount_z = number(mount[2], index(mount_field, 2));
        lidar.mount_yaw = number(mount[3], index(mount_field, 3)) * kDegToRad;
      }
      lidar.beam_count = static_cast<int>(
          number(entry, lidar_field, "beam_count", lidar.beam_count, 1.0, 100000.0));
      lidar.angle_min =
          number(entry, lidar_field, "angle_min_deg", lidar.angle_min / kDegToRad, -180.0, 180.0) *
          kDegToRad;
      lidar.angle_increment = number(entry, lidar_field, "angle_increment_deg",
                                     lidar.angle_increment / kDegToRad, 0.01, 10.0) *
                              kDegToRad;
      lidar.range_min = number(entry, lidar_field, "range_min", lidar.range_min, 0.0, 10.0);
      lidar.range_max = number(entry, lidar_field, "range_max", lidar.range_max, 0.5, 200.0);
      lidar.rate_hz = number(entry, lidar_field, "rate_hz", lidar.rate_hz, 1.0, 200.0);
      lidar.time_offset = number(entry, lidar_field, "time_offset", 0.0, 0.0, 1.0);
      lidar.range_noise_sigma =
          number(entry, lidar_field, "range_noise_sigma", lidar.range_noise_sigma, 0.0, 0.5);
      lidar.range_noise_per_m = number(entry, lidar_field, "range_noise_per_m", 0.0, 0.0, 0.05);
      lidar.dropout_probability =
          number(entry, lidar_field, "dropout_probability", lidar.dropout_probability, 0.0, 1.0);
      lidar.sweep = boolean(entry, lidar_field, "sweep", false);
      lidar.mirror_hz = number(entry, lidar_field, "mirror_hz", 0.0, 0.0, 1000.0);
      lidar.mount_pitch = number(entry, lidar_field, "mount_pitch_deg", 0.0, -5.0, 5.0) * kDegToRad;
      lidar.mount_roll = number(entry, lidar_field, "mount_roll_deg", 0.0, -5.0, 5.0) * kDegToRad;
      try {
        lidar.validate();
      } catch (const std::invalid_argument& error) {
        fail(lidar_field, error.what());
      }
      result.push_back(lidar);
    }
    return result;
  }

  // The realistic sensor model runs only with the realistic physics, so its lidar settings would
  // silently do nothing without it.
  void requirePhysicsForRealisticLidars(const Scene& scene) const {
    for (std::size_t i = 0; i < scene.lidars.size(); ++i) {
      const LidarSpec& lidar = scene.lidars[i];
      if (scene.physics.enabled) break;
      if (lidar.sweep || lidar.mount_pitch != 0.0 || lidar.mount_roll != 0.0) {
        fail(index("lidars", i),
             "sweep and mount tilts need the physics section (the realistic sensor model)");
      }
    }
  }

  std::vector<PersonSpec> people(const YAML::Node& node, double duration) const {
    std::vector<PersonSpec> result;
    if (!node) return result;
    const std::string field = "people";
    if (!node.IsSequence()) fail(field, "expected a list of people");
    for (std::size_t i = 0; i < node.size(); ++i) {
      const YAML::Node entry = node[i];
      const std::string person_field = index(field, i);
      requireMap(entry, person_field);
      rejectUnknownKeys(entry, person_field,
                        {"name", "radius", "speed", "start_time", "end_time", "loop", "waypoints",
                         "legs", "leg_radius"});
      PersonSpec person;
      person.name = text(entry, person_field, "name", "person" + std::to_string(i));
      person.radius = number(entry, person_field, "radius", person.radius, 0.05, 1.0);
      person.speed = number(entry, person_field, "speed", person.speed, 0.05, 3.0);
      person.start_time = number(entry, person_field, "start_time", 0.0, 0.0, duration);
      person.end_time = number(entry, person_field, "end_time", person.end_time, 0.0, 1e9);
      if (person.end_time <= person.start_time) {
        fail(join(person_field, "end_time"), "must be after start_time");
      }
      person.loop = boolean(entry, person_field, "loop", false);
      person.legs = boolean(entry, person_field, "legs", false);
      person.leg_radius = number(entry, person_field, "leg_radius", person.leg_radius, 0.02, 0.2);
      const std::string waypoints_field = join(person_field, "waypoints");
      const YAML::Node waypoints = entry["waypoints"];
      if (!waypoints) fail(waypoints_field, "missing (required)");
      if (!waypoints.IsSequence() || waypoints.size() == 0) {
        fail(waypoints_field, "expected a non-empty list of [x, y] or [x, y, pause_s]");
      }
      for (std::size_t k = 0; k < waypoints.size(); ++k) {
        PersonWaypoint waypoint;
        waypoint.position = point(waypoints[k], index(waypoints_field, k), &waypoint.pause);
        if (waypoint.pause < 0.0) fail(index(index(waypoints_field, k), 2), "pause must be >= 0");
        person.waypoints.push_back(waypoint);
      }
      try {
        Pedestrian check(person);
      } catch (const std::invalid_argument& error) {
        fail(join(person_field, "radius"), error.what());
      }
      result.push_back(person);
    }
    return result;
  }

  // People are solid: a path through a pillar or a desk would fuse the person with structure in
  // a way no real scene can, so such a scene is an error, not a harder test.
  void rejectPathsThroughWalls(const std::vector<PersonSpec>& people, const World& world) const {
    for (std::size_t i = 0; i < people.size(); ++i) {
      const std::optional<WallCollision> collision = findWallCollision(people[i], world);
      if (!collision) continue;
      std::ostringstream message;
      message << "the walk from (" << collision->from.x() << ", " << collision->from.y() << ") to ("
              << collision->to.x() << ", " << collision->to.y() << ") runs into a wall at ("
              << collision->at.x() << ", " << collision->at.y()
              << "): people cannot pass through walls";
      fail(index(join(index("people", i), "waypoints"), collision->waypoint), message.str());
    }
  }

  TrajectorySpec robot(const YAML::Node& node) const {
    const std::string field = "robot";
    if (!node) fail(field, "missing (required)");
    requireMap(node, field);
    rejectUnknownKeys(
        node, field,
        {"speed", "turn_rate_deg", "start_delay", "initial_yaw_deg", "loop", "waypoints"});
    TrajectorySpec spec;
    spec.speed = number(node, field, "speed", spec.speed, 0.05, 2.0);
    spec.turn_rate = number(node, field, "turn_rate_deg", 45.0, 1.0, 360.0) * kDegToRad;
    spec.start_delay = number(node, field, "start_delay", 1.0, 0.0, 600.0);
    if (node["initial_yaw_deg"]) {
      spec.initial_yaw = number(node, field, "initial_yaw_deg", 0.0, -360.0, 360.0) * kDegToRad;
    }
    spec.loop = boolean(node, field, "loop", false);
    const std::string waypoints_field = join(field, "waypoints");
    const YAML::Node waypoints = node["waypoints"];
    if (!waypoints) fail(waypoints_field, "missing (required)");
    if (!waypoints.IsSequence() || waypoints.size() == 0) {
      fail(waypoints_field, "expected a non-empty list of [x, y] or [x, y, pause_s]");
    }
    for (std::size_t i = 0; i < waypoints.size(); ++i) {
      double pause = 0.0;
      spec.waypoints.push_back(point(waypoints[i], index(waypoints_field, i), &pause));
      if (pause < 0.0) fail(index(index(waypoints_field, i), 2), "pause must be >= 0");
      if (pause > 0.0) spec.pauses.resize(spec.waypoints.size(), 0.0);
      if (pause > 0.0) spec.pauses.back() = pause;
    }
    return spec;
  }

  void sensors(const YAML::Node& node, std::vector<LidarSpec>& lidars) const {
    if (!node) return;
    const std::string field = "sensors";
    requireMap(node, field);
    rejectUnknownKeys(
        node, field,
        {"rate_hz", "range_min", "range_max", "range_noise_sigma", "dropout_probability",
         "rear_time_offset", "beam_count", "angle_min_deg", "angle_increment_deg"});
    for (LidarSpec& lidar : lidars) {
      lidar.rate_hz = number(node, field, "rate_hz", lidar.rate_hz, 1.0, 200.0);
      lidar.range_min = number(node, field, "range_min", lidar.range_min, 0.0, 10.0);
      lidar.range_max = number(node, field, "range_max", lidar.range_max, 0.5, 200.0);
      lidar.range_noise_sigma =
          number(node, field, "range_noise_sigma", lidar.range_noise_sigma, 0.0, 0.5);
      lidar.dropout_probability =
          number(node, field, "dropout_probability", lidar.dropout_probability, 0.0, 1.0);
      lidar.beam_count =
          static_cast<int>(number(node, field, "beam_count", lidar.beam_count, 1.0, 100000.0));
      lidar.angle_min =
          number(node, field, "angle_min_deg", lidar.angle_min / kDegToRad, -180.0, 180.0) *
          kDegToRad;
      lidar.angle_increment = number(node, field, "angle_increment_deg",
                                     lidar.angle_increment / kDegToRad, 0.01, 10.0) *
                              kDegToRad;
    }
    if (lidars.size() > 1) {
      lidars[1].time_offset = number(node, field, "rear_time_offset", 0.5 / lidars[1].rate_hz, 0.0,
                                     1.0 / lidars[1].rate_hz);
    }
    if (lidars.front().range_min >= lidars.front().range_max) {
      fail(join(field, "range_max"), "must be greater than range_min");
    }
  }

  Scene scene(const YAML::Node& root) const {
    if (!root || !root.IsMap()) fail("", "expected a YAML mapping at the top level");
    rejectUnknownKeys(root, "",
                      {"name", "description", "duration", "seed", "materials", "physics", "walls",
                       "people", "robot", "setup", "lidars", "sensors", "odometry", "logger",
                       "tf_rate_hz", "odom_rate_hz"});
    Scene scene;
    scene.name = text(root, "", "name", "");
    if (scene.name.empty()) fail("name", "missing (required)");
    scene.description = text(root, "", "description", "");
    scene.duration = requiredNumber(root, "", "duration", 0.1, 3600.0);
    scene.seed = static_cast<std::uint32_t>(number(root, "", "seed", 1.0, 0.0, 4294967295.0));
    if (root["materials"] && root["physics"]) {
      fail("physics",
           "give either materials (the ideal beam model) or physics (the realistic one)");
    }
    scene.materials = materials(root["materials"]);
    scene.physics = physics(root["physics"]);
    walls(root["walls"], scene.world);
    scene.people = people(root["people"], scene.duration);
    rejectPathsThroughWalls(scene.people, scene.world);
    scene.robot = robot(root["robot"]);
    if (root["setup"] && root["lidars"]) fail("lidars", "give either setup or lidars, not both");
    if (root["setup"]) {
      try {
        const SensorSetup& setup = sensorSetup(text(root, "", "setup", ""));
        scene.lidars = setup.lidars;
        scene.logger = setup.logger;
      } catch (const std::invalid_argument& error) {
        fail("setup", error.what());
      }
    } else if (root["lidars"]) {
      scene.lidars = lidars(root["lidars"]);
    } else {
      scene.lidars = defaultWheelchairLidars();
    }
    sensors(root["sensors"], scene.lidars);
    requirePhysicsForRealisticLidars(scene);
    if (root["logger"]) scene.logger = logger(root["logger"]);
    scene.odometry = odometry(root["odometry"]);
    scene.tf_rate_hz = number(root, "", "tf_rate_hz", scene.tf_rate_hz, 50.0, 1000.0);
    scene.odom_rate_hz = number(root, "", "odom_rate_hz", scene.odom_rate_hz, 1.0, 1000.0);
    return scene;
  }

 private:
  std::string source_;
};

}  // namespace

Scene parseScene(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& error) {
    throw SceneError(source, "", std::string("invalid YAML: ") + error.what());
  }
  Parser parser(source);
  try {
    return parser.scene(root);
  } catch (const SceneError&) {
    throw;
  } catch (const std::exception& error) {  // e.g. a yaml-cpp conversion we did not anticipate
    throw SceneError(source, "", error.what());
  }
}

Scene loadScene(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw SceneError(path, "", "cannot open scene file");
  std::ostringstream contents;
  contents << file.rdbuf();
  return parseScene(contents.str(), path);
}

}  // namespace rfm::sim
