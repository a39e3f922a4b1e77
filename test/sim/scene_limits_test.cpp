// Scene values that would hang rfm_sim, exhaust its memory or overflow its arithmetic are
// refused, naming the field; values just inside the limits still load.
#include <gtest/gtest.h>

#include <string>

#include "reflectance_field_map/sim/scene.h"

namespace rfm::sim {
namespace {

// A scene with one wall (`wall`, a flow mapping) and one person walking `walk`.
std::string sceneWith(const std::string& wall, const std::string& walk = "[[0, 1], [2, 1]]") {
  return "name: limits\nduration: 10\nwalls:\n  - " + wall + "\npeople:\n  - {waypoints: " + walk +
         "}\nrobot: {waypoints: [[-1, -1], [3, -1]]}\n";
}

const char* kGlassPane = "{type: segment, material: glass, points: [[0, 0], [3, 0]]}";

// The SceneError of parsing `text`, or fails the test.
SceneError parseError(const std::string& text) {
  try {
    parseScene(text, "limits.yaml");
  } catch (const SceneError& error) {
    return error;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return SceneError("", "", "");
}

TEST(SceneLimitsTest, TheBaseSceneLoads) {
  EXPECT_EQ(parseScene(sceneWith(kGlassPane)).world.surfaceCount(), 3u);  // frame, pane, frame
}

TEST(SceneLimitsTest, MicroscopicMullionSpacingIsRefused) {
  // 1e-6 m over a 3 m pane would make three million panes (rfm_sim made no output in 60 s).
  const SceneError error = parseError(sceneWith(
      "{type: segment, material: glass, points: [[0, 0], [3, 0]], mullion_spacing: 1e-6}"));
  EXPECT_EQ(error.field(), "walls[0].mullion_spacing");
  EXPECT_NE(std::string(error.what()).find("at least 0.1 m"), std::string::npos) << error.what();
}

TEST(SceneLimitsTest, MullionsCloserThanTwiceTheFrameAreRefused) {
  EXPECT_EQ(parseError(sceneWith("{type: segment, material: glass, points: [[0, 0], [3, 0]], "
                                 "frame: 0.3, mullion_spacing: 0.5}"))
                .field(),
            "walls[0].mullion_spacing");
  EXPECT_EQ(parseScene(sceneWith("{type: segment, material: glass, points: [[0, 0], [3, 0]], "
                                 "frame: 0.3, mullion_spacing: 0.6}"))
                .world.surfaceCount(),
            11u);  // frame, 5 panes, 4 mullions, frame
}

TEST(SceneLimitsTest, AWallOfTooManyPanesIsRefused) {
  // A 1000 m wall of 0.1 m panes: 20000 surfaces (with 1e-6 m ones, std::bad_alloc).
  const SceneError error = parseError(sceneWith(
      "{type: segment, material: glass, points: [[0, -10], [1000, -10]], mullion_spacing: 0.1}"));
  EXPECT_EQ(error.field(), "walls[0].mullion_spacing");
  EXPECT_NE(std::string(error.what()).find("at most 2000"), std::string::npos) << error.what();
  // The same wall with a mullion every 1.5 m (667 panes) is a scene.
  EXPECT_EQ(parseScene(sceneWith("{type: segment, material: glass, points: [[0, -10], [1000, "
                                 "-10]], mullion_spacing: 1.5}"))
                .world.surfaceCount(),
            2u * 667u + 1u);
  // Arcs count the same way: 2 pi * 200 m of 0.2 m panes.
  EXPECT_EQ(parseError(sceneWith("{type: arc, material: glass, center: [0, 0], radius: 200, "
                                 "start_deg: 0, end_deg: 360, mullion_spacing: 0.2}"))
                .field(),
            "walls[0].mullion_spacing");
}

TEST(SceneLimitsTest, FarAwayPointsAreRefusedNotOverflowed) {
  // A walk to y = -2e8 crossed the wall unchecked: its step count overflowed an int.
  const SceneError walk = parseError(sceneWith(kGlassPane, "[[1, 1], [1, -2e8]]"));
  EXPECT_EQ(walk.field(), "people[0].waypoints[1][1]");
  EXPECT_NE(std::string(walk.what()).find("within 1000 m"), std::string::npos) << walk.what();
  // The same walk to y = -100 is a walk through the pane.
  EXPECT_NE(std::string(parseError(sceneWith(kGlassPane, "[[1, 1], [1, -100]]")).what())
                .find("cannot pass through walls"),
            std::string::npos);
  EXPECT_EQ(parseError(sceneWith("{type: segment, material: diffuse, points: [[0, 0], [1e9, 0]]}"))
                .field(),
            "walls[0].points[1][0]");
  EXPECT_EQ(parseError("name: far\nduration: 10\nwalls:\n  - " + std::string(kGlassPane) +
                       "\nrobot: {waypoints: [[0, 1], [0, 5000]]}\n")
                .field(),
            "robot.waypoints[1][1]");
}

}  // namespace
}  // namespace rfm::sim
