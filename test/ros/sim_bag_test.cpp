// The live node fed by a simulated bag, as replay.launch feeds it: rfm_sim writes the test scene
// (glass_and_pedestrian.yaml: a framed glass pane in the north wall, a pedestrian walking past
// the robot and leaving) and `rosbag play --clock` replays it to rfm_node on simulated time.
// Checks that /rfm/map (kept current with /rfm/map_updates) has the pane occupied and the
// pedestrian's path free, and that the node labelled the pedestrian's beams MOTION on the way.
// Every wait is a condition with a deadline, never a fixed sleep.
#include "map_copy.h"
#include "reflectance_field_map/RayLabels.h"

#include <gtest/gtest.h>
#include <ros/ros.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace {

using rfm_test::MapCopy;
using rfm_test::waitFor;

// The scene's geometry (glass_and_pedestrian.yaml); it starts at t = 1000 s and lasts 18 s.
constexpr double kPaneY = 2.525;
constexpr double kPaneHalfWidth = 1.5;
constexpr double kPathY = -1.2;  // the pedestrian walks from x = 5 to x = -5, gone by t = 12 s
constexpr double kSceneEnd = 1018.0;

class LabelCounter {
 public:
  void onLabels(const reflectance_field_map::RayLabelsConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++scans_;
    for (uint8_t label : msg->labels)
      motion_ += label == reflectance_field_map::RayLabels::MOTION;
  }
  int scans() {
    std::lock_guard<std::mutex> lock(mutex_);
    return scans_;
  }
  long motion() {
    std::lock_guard<std::mutex> lock(mutex_);
    return motion_;
  }

 private:
  std::mutex mutex_;
  int scans_ = 0;
  long motion_ = 0;
};

// Starts `rosbag play` on `bag`; returns its pid, or -1.
pid_t playBag(const std::string& bag) {
  // Played only once the mapper subscribes to every topic (no fixed delay); /odom and the
  // simulator's ground truth are left out, as nobody subscribes to them here.
  std::vector<std::string> args = {"rosbag",
                                   "play",
                                   "--clock",
                                   "--quiet",
                                   "--rate",
                                   "2",
                                   "--wait-for-subscribers",
                                   bag,
                                   "--topics",
                                   "/scan_front",
                                   "/scan_rear",
                                   "/tf",
                                   "/tf_static"};
  std::vector<char*> argv;
  for (std::string& arg : args)
    argv.push_back(arg.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  return posix_spawnp(&pid, "rosbag", nullptr, nullptr, argv.data(), environ) == 0 ? pid : -1;
}

TEST(SimulatedBag, PaneOccupiedAndPedestrianPathFree) {
  char dir_template[] = "/tmp/rfm_sim_bag_test_XXXXXX";
  ASSERT_NE(mkdtemp(dir_template), nullptr);
  const std::string dir = dir_template;
  const std::string bag = dir + "/scene.bag";
  const std::string simulate = std::string(RFM_SIM_BINARY) + " --scene " + RFM_TEST_SCENE +
                               " --out " + bag + " > " + dir + "/sim.log 2>&1";
  ASSERT_EQ(std::system(simulate.c_str()), 0) << simulate;

  ros::NodeHandle nh;
  MapCopy map;
  LabelCounter labels;
  ros::AsyncSpinner spinner(2);
  std::vector<ros::Subscriber> subs = {
      nh.subscribe("/rfm/map", 5, &MapCopy::onMap, &map),
      nh.subscribe("/rfm/map_updates", 50, &MapCopy::onUpdate, &map),
      nh.subscribe("/rfm/scan_front/labels", 500, &LabelCounter::onLabels, &labels),
      nh.subscribe("/rfm/scan_rear/labels", 500, &LabelCounter::onLabels, &labels)};
  spinner.start();
  // Every subscription connected before the bag plays: the node labels a topic's scans only
  // while someone listens to its labels, so a late connection would lose the first seconds.
  ASSERT_TRUE(waitFor(
      [&] {
        return std::all_of(subs.begin(), subs.end(),
                           [](const ros::Subscriber& sub) { return sub.getNumPublishers() > 0; });
      },
      30.0))
      << "rfm node did not come up";

  const pid_t player = playBag(bag);
  ASSERT_GT(player, 0) << "cannot start rosbag play";
  int status = -1;
  const bool played = waitFor([&] { return waitpid(player, &status, WNOHANG) == player; }, 120.0);
  if (!played) kill(player, SIGINT);
  ASSERT_TRUE(played) << "rosbag play did not finish";
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "rosbag play failed";

  // The map as the node left it at the bag's end: its last update comes within a motion-removal
  // period (0.5 s of the scans' clock) of the last scan.
  ASSERT_TRUE(waitFor([&] { return map.lastChange().toSec() >= kSceneEnd - 2.0; }, 20.0))
      << "last map change at " << map.lastChange().toSec() << " s";

  for (double x = -kPaneHalfWidth + 0.2; x <= kPaneHalfWidth - 0.2; x += 0.3)
    EXPECT_TRUE(map.occupiedNear(x, kPaneY)) << "pane not occupied at x = " << x;

  // Every cell of the pedestrian's path that the robot passed by is free (0), neither occupied
  // nor unknown.
  std::ostringstream not_free;
  for (double x = -3.0; x <= 3.0; x += 0.1) {
    const int value = map.at(x, kPathY);
    if (value != 0) not_free << " x=" << x << ":" << value;
  }
  EXPECT_TRUE(not_free.str().empty()) << "pedestrian's path not free at" << not_free.str();

  // The path is free because the pedestrian was seen and removed as motion, not because it was
  // never seen: the node labelled the pedestrian's beams MOTION in the scans it published (the
  // simulator's truth has 19372 of them; the node, judging each scan against the map so far,
  // labels 6.0 k: where the pedestrian stands is solid until the robot sees through it, so only
  // the trail they left is motion by the next motion removal).
  // Between full maps only the changed windows travel: within the scene's 18 s, shorter than the
  // 30 s republishing period, a full map goes out only when the map's bounds grew.
  std::cout << "map: " << map.full_maps << " full, " << map.updates << " updates\n";
  EXPECT_EQ(map.full_maps_same_bounds, 0) << "full maps sent though the bounds stayed";
  EXPECT_GT(map.updates, map.full_maps);

  std::cout << "labels: " << labels.scans() << " scans, " << labels.motion() << " MOTION beams\n";
  EXPECT_GT(labels.scans(), 1000);
  EXPECT_GT(labels.motion(), 3000) << "MOTION labels over " << labels.scans() << " scans";

  std::filesystem::remove_all(dir);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rfm_sim_bag_test");
  return RUN_ALL_TESTS();
}
