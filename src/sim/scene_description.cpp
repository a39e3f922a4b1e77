#include "reflectance_field_map/sim/scene_description.h"

#include <charconv>
#include <cmath>
#include <sstream>

namespace rfm::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

std::string point(const Eigen::Vector2d& p) {
  return "[" + formatNumber(p.x()) + ", " + formatNumber(p.y()) + "]";
}

std::string points(const std::vector<Eigen::Vector2d>& list) {
  std::string text = "[";
  for (std::size_t i = 0; i < list.size(); ++i)
    text += (i ? ", " : "") + point(list[i]);
  return text + "]";
}

// A YAML double-quoted string.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// Degrees of an angle the loader turned into radians, without the conversion's last-digit noise.
double degrees(double radians) {
  return std::round(radians / kDegToRad * 1e9) / 1e9;
}

void writePhysics(std::ostream& out, const RealisticPhysics& p) {
  out << "physics:\n"
      << "  return_cone_deg: " << formatNumber(p.return_cone_deg) << "\n"
      << "  bump_tilt_deg: " << formatNumber(p.bump_tilt_deg) << "\n"
      << "  bump_correlation_s: " << formatNumber(p.bump_correlation_s) << "\n"
      << "  standing_tilt_deg: " << formatNumber(p.standing_tilt_deg) << "\n"
      << "  refractive_index: " << formatNumber(p.refractive_index) << "\n"
      << "  empty_echo_probability: " << formatNumber(p.empty_echo_probability) << "\n"
      << "  empty_echo_decay_deg: " << formatNumber(p.empty_echo_decay_deg) << "\n"
      << "  metal_lobe_deg: " << formatNumber(p.metal_lobe_deg) << "\n"
      << "  metal_tail_probability: " << formatNumber(p.metal_tail_probability) << "\n"
      << "  metal_tail_decay_deg: " << formatNumber(p.metal_tail_decay_deg) << "\n"
      << "  diffuse_max_incidence_deg: " << formatNumber(p.diffuse_max_incidence_deg) << "\n"
      << "  grazing_dropout: " << formatNumber(p.grazing_dropout) << "\n"
      << "  range_dropout: " << formatNumber(p.range_dropout) << "\n"
      << "  gloss_probability: " << formatNumber(p.gloss_probability) << "\n"
      << "  max_interactions: " << p.max_interactions << "\n";
}

void writeOdometry(std::ostream& out, const OdometryDrift& d) {
  out << "odometry:\n"
      << "  xy_noise: " << formatNumber(d.xy_noise) << "\n"
      << "  yaw_noise_deg: " << formatNumber(d.yaw_noise_deg) << "\n"
      << "  turn_noise_deg: " << formatNumber(d.turn_noise_deg) << "\n"
      << "  scale_error: " << formatNumber(d.scale_error) << "\n"
      << "  turn_scale_error: " << formatNumber(d.turn_scale_error) << "\n"
      << "  yaw_bias_deg_per_m: " << formatNumber(d.yaw_bias_deg_per_m) << "\n";
}

void writeLidar(std::ostream& out, const LidarSpec& l) {
  out << "  - {topic: " << l.topic << ", frame_id: " << l.frame_id << ", mount: ["
      << formatNumber(l.mount_x) << ", " << formatNumber(l.mount_y) << ", "
      << formatNumber(l.mount_z) << ", " << formatNumber(degrees(l.mount_yaw)) << "],\n"
      << "     beam_count: " << l.beam_count
      << ", angle_min_deg: " << formatNumber(degrees(l.angle_min))
      << ", angle_increment_deg: " << formatNumber(degrees(l.angle_increment))
      << ", rate_hz: " << formatNumber(l.rate_hz)
      << ", time_offset: " << formatNumber(l.time_offset) << ",\n"
      << "     range_min: " << formatNumber(l.range_min)
      << ", range_max: " << formatNumber(l.range_max)
      << ", range_noise_sigma: " << formatNumber(l.range_noise_sigma)
      << ", range_noise_per_m: " << formatNumber(l.range_noise_per_m)
      << ", dropout_probability: " << formatNumber(l.dropout_probability) << ",\n"
      << "     sweep: " << (l.sweep ? "true" : "false")
      << ", mirror_hz: " << formatNumber(l.mirror_hz)
      << ", mount_pitch_deg: " << formatNumber(degrees(l.mount_pitch))
      << ", mount_roll_deg: " << formatNumber(degrees(l.mount_roll)) << "}\n";
}

void writeWall(std::ostream& out, const WallDescription& w) {
  out << "  - {type: ";
  switch (w.type) {
    case WallDescription::Type::kSegment:
      out << "segment, material: " << materialName(w.material) << ", points: " << points(w.points);
      break;
    case WallDescription::Type::kPolyline:
      out << "polyline, material: " << materialName(w.material) << ", points: " << points(w.points);
      if (w.closed) out << ", closed: true";
      break;
    case WallDescription::Type::kArc:
      out << "arc, material: " << materialName(w.material) << ", center: " << point(w.center)
          << ", radius: " << formatNumber(w.radius) << ", start_deg: " << formatNumber(w.start_deg)
          << ", end_deg: " << formatNumber(w.end_deg);
      break;
  }
  out << ", frame: " << formatNumber(w.frame);
  if (w.mullion_spacing > 0.0) out << ", mullion_spacing: " << formatNumber(w.mullion_spacing);
  if (w.dirt > 0.0) out << ", dirt: " << formatNumber(w.dirt);
  if (w.tilt_deg != 0.0) out << ", tilt_deg: " << formatNumber(w.tilt_deg);
  out << "}\n";
}

void writePerson(std::ostream& out, const PersonSpec& p) {
  out << "  - {name: " << p.name << ", radius: " << formatNumber(p.radius)
      << ", speed: " << formatNumber(p.speed) << ", start_time: " << formatNumber(p.start_time);
  if (std::isfinite(p.end_time)) out << ", end_time: " << formatNumber(p.end_time);
  if (p.loop) out << ", loop: true";
  if (p.legs) out << ", legs: true, leg_radius: " << formatNumber(p.leg_radius);
  out << ",\n     waypoints: [";
  for (std::size_t i = 0; i < p.waypoints.size(); ++i) {
    const PersonWaypoint& w = p.waypoints[i];
    out << (i ? ", " : "") << "[" << formatNumber(w.position.x()) << ", "
        << formatNumber(w.position.y());
    if (w.pause > 0.0) out << ", " << formatNumber(w.pause);
    out << "]";
  }
  out << "]}\n";
}

}  // namespace

std::string formatNumber(double value) {
  if (value == 0.0) return "0";  // also for -0
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string sceneToYaml(const SceneDescription& scene) {
  std::ostringstream out;
  std::istringstream comment(scene.comment);
  for (std::string line; std::getline(comment, line);)
    out << "# " << line << "\n";
  out << "name: " << scene.name << "\n"
      << "description: " << quoted(scene.description) << "\n"
      << "duration: " << formatNumber(scene.duration) << "\n"
      << "seed: " << scene.seed << "\n";
  if (scene.physics) writePhysics(out, *scene.physics);
  if (scene.odometry) writeOdometry(out, *scene.odometry);
  if (scene.logger.enabled()) {
    out << "logger: {keep_every_m: " << formatNumber(scene.logger.keep_every_m)
        << ", keep_every_deg: " << formatNumber(scene.logger.keep_every_deg) << "}\n";
  }
  if (!scene.lidars.empty()) {
    out << "lidars:\n";
    for (const LidarSpec& lidar : scene.lidars)
      writeLidar(out, lidar);
  }
  out << "walls:\n";
  for (const WallDescription& wall : scene.walls)
    writeWall(out, wall);
  if (!scene.people.empty()) {
    out << "people:\n";
    for (const PersonSpec& person : scene.people)
      writePerson(out, person);
  }
  out << "robot:\n"
      << "  speed: " << formatNumber(scene.robot.speed) << "\n"
      << "  turn_rate_deg: " << formatNumber(scene.robot.turn_rate_deg) << "\n"
      << "  start_delay: " << formatNumber(scene.robot.start_delay) << "\n"
      << "  waypoints: [";
  for (std::size_t i = 0; i < scene.robot.waypoints.size(); ++i) {
    const Eigen::Vector2d& w = scene.robot.waypoints[i];
    out << (i ? ", " : "") << "[" << formatNumber(w.x()) << ", " << formatNumber(w.y());
    if (i < scene.robot.pauses.size() && scene.robot.pauses[i] > 0.0) {
      out << ", " << formatNumber(scene.robot.pauses[i]);
    }
    out << "]";
  }
  out << "]\n";
  return out.str();
}

void addWall(World& world, const WallDescription& wall) {
  SurfaceFinish finish;
  finish.dirt = wall.dirt;
  finish.tilt = wall.tilt_deg * kDegToRad;
  if (wall.type == WallDescription::Type::kArc) {
    world.addFramedArc(wall.center, wall.radius, wall.start_deg * kDegToRad,
                       wall.end_deg * kDegToRad, wall.material, wall.frame, wall.mullion_spacing,
                       finish);
    return;
  }
  std::vector<Eigen::Vector2d> corners = wall.points;
  if (wall.closed) corners.push_back(corners.front());
  for (std::size_t k = 0; k + 1 < corners.size(); ++k) {
    world.addFramedSegment(corners[k], corners[k + 1], wall.material, wall.frame,
                           wall.mullion_spacing, finish);
  }
}

}  // namespace rfm::sim
