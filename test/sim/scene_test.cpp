// Scene files: every shipped scene loads and is sensible; bad files are rejected naming the field.
#include <gtest/gtest.h>

#include <dirent.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "reflectance_field_map/sim/scene.h"

namespace rfm::sim {
namespace {

std::vector<std::string> shippedScenes() {
  std::vector<std::string> names;
  if (DIR* directory = opendir(RFM_SCENE_DIR)) {
    while (const dirent* entry = readdir(directory)) {
      const std::string name = entry->d_name;
      if (name.size() > 5 && name.substr(name.size() - 5) == ".yaml") names.push_back(name);
    }
    closedir(directory);
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(SceneFilesTest, AllRequiredScenesAreShipped) {
  const std::vector<std::string> names = shippedScenes();
  for (const char* required :
       {"atrium.yaml", "glass_wall.yaml", "curved_glass.yaml", "corridor_pedestrian.yaml",
        "mirror_metal.yaml", "crowded_lobby.yaml", "parallel_panes.yaml", "office.yaml"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
  }
}

TEST(SceneFilesTest, EveryShippedSceneLoadsAndValidates) {
  for (const std::string& file : shippedScenes()) {
    SCOPED_TRACE(file);
    Scene scene;
    ASSERT_NO_THROW(scene = loadScene(std::string(RFM_SCENE_DIR) + "/" + file));
    EXPECT_EQ(scene.name + ".yaml", file);
    EXPECT_GE(scene.duration, 40.0);
    EXPECT_LE(scene.duration, 120.0);
    EXPECT_GT(scene.world.surfaceCount(), 0u);
    ASSERT_EQ(scene.lidars.size(), 2u);
    EXPECT_NO_THROW(scene.materials.validate());
    // The robot stays inside the mapped area, and the area is a few tens of metres across.
    const auto [low, high] = scene.world.bounds();
    EXPECT_LT((high - low).maxCoeff(), 60.0);
    for (const Eigen::Vector2d& waypoint : scene.robot.waypoints) {
      EXPECT_TRUE((waypoint.array() > low.array()).all() && (waypoint.array() < high.array()).all())
          << waypoint.transpose();
    }
    for (const PersonSpec& person : scene.people) {
      EXPECT_GE(person.speed, 0.8) << person.name;
      EXPECT_LE(person.speed, 1.5) << person.name;
      EXPECT_GE(person.radius, 0.2);
      EXPECT_LE(person.radius, 0.3);
    }
    EXPECT_GE(scene.robot.speed, 0.5);
    EXPECT_LE(scene.robot.speed, 1.0);
  }
}

TEST(SceneFilesTest, OnlyTheControlSceneIsFreeOfShinySurfaces) {
  for (const std::string& file : shippedScenes()) {
    const Scene scene = loadScene(std::string(RFM_SCENE_DIR) + "/" + file);
    bool shiny = false;
    for (const auto& segment : scene.world.segments())
      shiny |= segment.material != Material::kDiffuse;
    for (const auto& arc : scene.world.arcs())
      shiny |= arc.material != Material::kDiffuse;
    EXPECT_EQ(shiny, file != "office.yaml") << file;
  }
}

const char* kValidScene = R"(
name: tiny
duration: 10
walls:
  - {type: segment, material: glass, points: [[0, 0], [4, 0]], frame: 0.1, mullion_spacing: 2}
  - {type: arc, material: diffuse, center: [0, 5], radius: 1, start_deg: 0, end_deg: 360}
people:
  - {speed: 1.0, start_time: 1, end_time: 8, waypoints: [[0, 1], [2, 1, 3.0]]}
robot:
  speed: 0.6
  waypoints: [[-1, -1], [3, -1]]
sensors: {rate_hz: 20, range_noise_sigma: 0.01}
)";

TEST(SceneParseTest, ParsesAllSections) {
  const Scene scene = parseScene(kValidScene, "tiny.yaml");
  EXPECT_EQ(scene.name, "tiny");
  EXPECT_DOUBLE_EQ(scene.duration, 10.0);
  // Framed glass segment: frame, pane, mullion, pane, frame.
  EXPECT_EQ(scene.world.segmentCount(), 5u);
  EXPECT_EQ(scene.world.arcCount(), 1u);
  ASSERT_EQ(scene.people.size(), 1u);
  EXPECT_DOUBLE_EQ(scene.people[0].waypoints[1].pause, 3.0);
  EXPECT_DOUBLE_EQ(scene.robot.speed, 0.6);
  EXPECT_DOUBLE_EQ(scene.lidars[0].rate_hz, 20.0);
  EXPECT_DOUBLE_EQ(scene.lidars[1].time_offset, 0.025);  // half a period at 20 Hz
}

// Replaces the first occurrence of `from` in the valid scene and returns the error's field.
std::string errorField(const std::string& from, const std::string& to) {
  std::string text = kValidScene;
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  try {
    parseScene(text, "bad.yaml");
  } catch (const SceneError& error) {
    EXPECT_NE(std::string(error.what()).find("bad.yaml"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find(error.field()), std::string::npos);
    return error.field();
  }
  ADD_FAILURE() << "no error for " << to;
  return "";
}

TEST(SceneParseTest, ErrorsNameTheBadField) {
  EXPECT_EQ(errorField("material: glass", "material: glas"), "walls[0].material");
  EXPECT_EQ(errorField("type: arc", "type: circle"), "walls[1].type");
  EXPECT_EQ(errorField("radius: 1", "radius: -1"), "walls[1].radius");
  EXPECT_EQ(errorField("duration: 10", "duration: ten"), "duration");
  EXPECT_EQ(errorField("duration: 10", "span: 10"), "span");  // unknown key
  EXPECT_EQ(errorField("[2, 1, 3.0]", "[2, 1, 3.0, 4]"), "people[0].waypoints[1]");
  EXPECT_EQ(errorField("end_time: 8", "end_time: 0.5"), "people[0].end_time");
  EXPECT_EQ(errorField("speed: 0.6", "sped: 0.6"), "robot.sped");
  EXPECT_EQ(errorField("speed: 0.6", "speed: 9"), "robot.speed");
  EXPECT_EQ(errorField("waypoints: [[-1, -1], [3, -1]]", "waypoints: []"), "robot.waypoints");
  EXPECT_EQ(errorField("rate_hz: 20", "rate_hz: x"), "sensors.rate_hz");
  EXPECT_EQ(errorField("points: [[0, 0], [4, 0]]", "points: [[0, 0]]"), "walls[0].points");
  EXPECT_EQ(errorField("name: tiny\n", ""), "name");
  // People are solid: no walking through a pane or a pillar, nor brushing through it.
  EXPECT_EQ(errorField("[[0, 1], [2, 1, 3.0]]", "[[0, 1], [2, -1, 3.0]]"),
            "people[0].waypoints[0]");
  EXPECT_EQ(errorField("[[0, 1], [2, 1, 3.0]]", "[[0, 1], [2, 1, 3.0], [0, 4.0]]"),
            "people[0].waypoints[1]");
  EXPECT_EQ(errorField("[[0, 1], [2, 1, 3.0]]", "[[0, 0.2], [2, 1, 3.0]]"),
            "people[0].waypoints[0]");
}

TEST(SceneFilesTest, ShippedScenesUseTheIdealModelOnly) {
  // Their bags are hashed to check refactors: the realistic physics, drift and logger (drawn
  // from streams of their own) stay off, so they simulate exactly as they always did.
  for (const std::string& file : shippedScenes()) {
    const Scene scene = loadScene(std::string(RFM_SCENE_DIR) + "/" + file);
    EXPECT_FALSE(scene.physics.enabled) << file;
    EXPECT_FALSE(scene.odometry.enabled) << file;
    EXPECT_FALSE(scene.logger.enabled()) << file;
    for (const LidarSpec& lidar : scene.lidars)
      EXPECT_FALSE(lidar.sweep) << file;
  }
}

TEST(SensorSetupsTest, SpanTheSensorsOfIssue35) {
  std::set<std::string> names;
  std::set<int> fields_of_view, lidar_counts;
  for (const SensorSetup& setup : sensorSetups()) {
    SCOPED_TRACE(setup.name);
    EXPECT_TRUE(names.insert(setup.name).second);
    lidar_counts.insert(static_cast<int>(setup.lidars.size()));
    for (const LidarSpec& lidar : setup.lidars) {
      EXPECT_NO_THROW(lidar.validate());
      const double step = lidar.angle_increment * 180.0 / M_PI;
      fields_of_view.insert(static_cast<int>(std::lround(lidar.beam_count * step / 90.0)) * 90);
      EXPECT_GE(step, 0.25 - 1e-9);
      EXPECT_LE(step, 1.0 + 1e-9);
      EXPECT_GE(lidar.rate_hz, 5.0);
      EXPECT_LE(lidar.rate_hz, 40.0);
      EXPECT_GE(lidar.range_max, 5.6 - 1e-9);
      EXPECT_LE(lidar.range_max, 80.0);
    }
  }
  EXPECT_EQ(sensorSetups().front().name, "wheelchair");
  EXPECT_EQ(fields_of_view, (std::set<int>{180, 270, 360}));
  EXPECT_EQ(lidar_counts, (std::set<int>{1, 2}));
  EXPECT_THROW(sensorSetup("kinect"), std::invalid_argument);
  // The default setup is the scenes' default: the same lidars, value for value.
  const std::vector<LidarSpec> wheelchair = sensorSetup("wheelchair").lidars;
  const std::vector<LidarSpec> scene_default = parseScene(kValidScene).lidars;
  ASSERT_EQ(wheelchair.size(), 2u);
  EXPECT_EQ(wheelchair[1].topic, "/scan_rear");
  EXPECT_DOUBLE_EQ(wheelchair[1].time_offset, 0.0125);
  EXPECT_DOUBLE_EQ(wheelchair[0].angle_min, defaultWheelchairLidars()[0].angle_min);
  EXPECT_DOUBLE_EQ(scene_default[0].angle_increment, wheelchair[0].angle_increment);
}

TEST(SceneParseTest, ReadsSetupsLidarsPhysicsOdometryAndLogger) {
  const Scene setup = parseScene(R"(
name: s
duration: 5
setup: carmen_sparse
walls: [{type: segment, material: diffuse, points: [[0, 0], [1, 0]]}]
robot: {waypoints: [[0, 1]]}
)");
  ASSERT_EQ(setup.lidars.size(), 1u);
  EXPECT_EQ(setup.lidars[0].beam_count, 361);
  EXPECT_DOUBLE_EQ(setup.logger.keep_every_deg, 30.0);  // the setup's logger
  EXPECT_FALSE(setup.physics.enabled);
  EXPECT_FALSE(setup.odometry.enabled);

  const Scene custom = parseScene(R"(
name: c
duration: 5
physics: {return_cone_deg: 1.5, metal_lobe_deg: 9}
odometry:
logger: {keep_every_m: 0.5}
lidars:
  - {topic: /scan, frame_id: laser, mount: [0.2, 0, 0.3, 180], beam_count: 181,
     angle_min_deg: -90, angle_increment_deg: 1, rate_hz: 5, range_max: 80, sweep: true,
     mirror_hz: 75, mount_pitch_deg: 0.5}
walls:
  - {type: segment, material: glass, points: [[0, 0], [4, 0]], dirt: 0.01, tilt_deg: -0.3}
people:
  - {radius: 0.4, legs: true, leg_radius: 0.07, waypoints: [[0, 2], [3, 2]]}
robot: {waypoints: [[0, 1]]}
)");
  EXPECT_TRUE(custom.physics.enabled);
  EXPECT_DOUBLE_EQ(custom.physics.return_cone_deg, 1.5);
  EXPECT_DOUBLE_EQ(custom.physics.metal_lobe_deg, 9.0);
  EXPECT_TRUE(custom.odometry.enabled);  // `odometry:` alone: the default drift
  EXPECT_DOUBLE_EQ(custom.odometry.xy_noise, OdometryDrift().xy_noise);
  EXPECT_DOUBLE_EQ(custom.logger.keep_every_m, 0.5);
  ASSERT_EQ(custom.lidars.size(), 1u);
  EXPECT_NEAR(custom.lidars[0].mount_yaw, M_PI, 1e-12);
  EXPECT_TRUE(custom.lidars[0].sweep);
  EXPECT_NEAR(custom.lidars[0].timeIncrement(), 1.0 / (360.0 * 75.0), 1e-12);
  EXPECT_NEAR(custom.lidars[0].mount_pitch, 0.5 * M_PI / 180.0, 1e-12);
  const int glass = 2;  // frame, pane, frame
  EXPECT_DOUBLE_EQ(custom.world.finish(glass - 1).dirt, 0.01);
  EXPECT_NEAR(custom.world.finish(glass - 1).tilt, -0.3 * M_PI / 180.0, 1e-12);
  EXPECT_TRUE(custom.people[0].legs);
  EXPECT_DOUBLE_EQ(custom.people[0].leg_radius, 0.07);
}

TEST(SceneParseTest, RejectsContradictionsAndSettingsThatWouldDoNothing) {
  EXPECT_EQ(errorField("sensors: {rate_hz: 20, range_noise_sigma: 0.01}",
                       "setup: wheelchair\nlidars: [{topic: /scan, frame_id: laser}]"),
            "lidars");
  EXPECT_EQ(errorField("sensors: {rate_hz: 20, range_noise_sigma: 0.01}", "setup: kinect"),
            "setup");
  EXPECT_EQ(errorField("duration: 10", "duration: 10\nmaterials: {}\nphysics: {}"), "physics");
  EXPECT_EQ(errorField("sensors: {rate_hz: 20, range_noise_sigma: 0.01}",
                       "lidars: [{topic: /scan, frame_id: laser, sweep: true}]"),
            "lidars[0]");
  EXPECT_EQ(errorField("sensors: {rate_hz: 20, range_noise_sigma: 0.01}",
                       "lidars: [{topic: /a, frame_id: l}, {topic: /a, frame_id: m}]"),
            "lidars[1].topic");
  EXPECT_EQ(errorField("sensors: {rate_hz: 20, range_noise_sigma: 0.01}",
                       "lidars: [{topic: /a, frame_id: l, beam_count: 0}]"),
            "lidars[0].beam_count");
  EXPECT_EQ(errorField("duration: 10", "duration: 10\nphysics: {return_cone_deg: 50}"),
            "physics.return_cone_deg");
  EXPECT_EQ(errorField("duration: 10", "duration: 10\nodometry: {xy_noise: 2}"),
            "odometry.xy_noise");
  EXPECT_EQ(errorField("duration: 10", "duration: 10\nlogger: {keep_every: 1}"),
            "logger.keep_every");
  EXPECT_EQ(errorField("frame: 0.1,", "frame: 0.1, dirt: 2,"), "walls[0].dirt");
  EXPECT_EQ(errorField("speed: 1.0, start_time: 1", "speed: 1.0, legs: true, start_time: 1"),
            "people[0].radius");  // a 0.25 m footprint is too small for walking legs
}

TEST(SceneParseTest, SyntaxErrorsAndMissingFilesAreReported) {
  EXPECT_THROW(parseScene("walls: [unclosed", "broken.yaml"), SceneError);
  try {
    loadScene("/nonexistent/scene.yaml");
    FAIL();
  } catch (const SceneError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/scene.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace rfm::sim
