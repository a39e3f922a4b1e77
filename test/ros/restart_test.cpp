// rfm_node killed (SIGKILL, as a power cut or the OOM killer would) and started again: ~load_map
// of the state saved before the kill resumes the map exactly as saved (saved again, it gives the
// same map and as much evidence), and mapping goes on from there. The test starts the node itself
// (restart_node.test only brings the master) and feeds it the robot in a room of room_world.h on
// wall time.
#include "map_copy.h"
#include "reflectance_field_map/LoadMap.h"
#include "reflectance_field_map/RfmStats.h"
#include "reflectance_field_map/SaveMap.h"
#include "room_world.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace {

using rfm_test::MapCopy;
using rfm_test::RoomWorld;
using rfm_test::waitFor;

// Starts rfm_node as /rfm with its maps under `dir`, its output in dir/node_N.log; -1 on failure.
pid_t startNode(const std::string& dir, int run, const std::string& extra = "") {
  std::vector<std::string> args = {RFM_NODE_BINARY, "__name:=rfm", "_map_directory:=" + dir,
                                   "__log:=" + dir + "/ros_" + std::to_string(run) + ".log"};
  if (!extra.empty()) args.push_back(extra);
  std::vector<char*> argv;
  for (std::string& arg : args)
    argv.push_back(arg.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  const std::string log = dir + "/node_" + std::to_string(run) + ".log";
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT, 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  const int failed = posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  return failed == 0 ? pid : -1;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

class Stats {
 public:
  void onStats(const reflectance_field_map::RfmStatsConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    latest_ = *msg;
  }
  uint64_t processed() {
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_.scans_processed;
  }
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    latest_ = reflectance_field_map::RfmStats();
  }

 private:
  std::mutex mutex_;
  reflectance_field_map::RfmStats latest_;
};

bool call(ros::ServiceClient& client, const std::string& path, std::string* message) {
  reflectance_field_map::SaveMap save;
  save.request.path = path;
  if (!client.call(save)) return false;
  *message = save.response.message;
  return save.response.success;
}

TEST(Restart, AKilledNodeResumesFromItsSavedMap) {
  char dir_template[] = "/tmp/rfm_restart_test_XXXXXX";
  ASSERT_NE(mkdtemp(dir_template), nullptr);
  const std::string dir = dir_template;

  ros::NodeHandle nh;
  MapCopy map;
  Stats stats;
  ros::AsyncSpinner spinner(2);
  std::vector<ros::Subscriber> subs = {
      nh.subscribe("/rfm/map", 5, &MapCopy::onMap, &map),
      nh.subscribe("/rfm/map_updates", 50, &MapCopy::onUpdate, &map),
      nh.subscribe("/rfm/stats", 10, &Stats::onStats, &stats)};
  spinner.start();
  RoomWorld world(nh);
  auto walls = [&] {
    return map.occupiedNear(0.0, rfm_test::kRoomHalfY) &&
           map.occupiedNear(rfm_test::kRoomHalfX, 0.0);
  };

  pid_t node = startNode(dir, 1);
  ASSERT_GT(node, 0);
  ASSERT_TRUE(waitFor([&] { return world.connected(); }, 30.0)) << "see " << dir << "/node_1.log";
  world.start();
  ASSERT_TRUE(waitFor(walls, 30.0));
  ros::ServiceClient save = nh.serviceClient<reflectance_field_map::SaveMap>("/rfm/save_map");
  ASSERT_TRUE(save.waitForExistence(ros::Duration(10.0)));
  world.paused_ = true;
  std::string message;
  ASSERT_TRUE(call(save, "before_kill", &message)) << message;

  kill(node, SIGKILL);
  int status = 0;
  ASSERT_EQ(waitpid(node, &status, 0), node);
  EXPECT_TRUE(WIFSIGNALED(status));
  // Nothing half-written is left beside the saved files.
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".part"), std::string::npos) << entry.path();

  stats.clear();
  node = startNode(dir, 2);
  ASSERT_GT(node, 0);
  ros::ServiceClient load = nh.serviceClient<reflectance_field_map::LoadMap>("/rfm/load_map");
  ASSERT_TRUE(waitFor([&] { return load.exists() && world.connected(); }, 30.0))
      << "see " << dir << "/node_2.log";
  reflectance_field_map::LoadMap resume;
  resume.request.path = "before_kill";
  ASSERT_TRUE(load.call(resume));
  ASSERT_TRUE(resume.response.success) << resume.response.message;
  save = nh.serviceClient<reflectance_field_map::SaveMap>("/rfm/save_map");
  ASSERT_TRUE(call(save, "after_restart", &message)) << message;
  EXPECT_EQ(readFile(dir + "/after_restart.pgm"), readFile(dir + "/before_kill.pgm"));
  // The same tiles of evidence (their order in the file follows a hash table's).
  EXPECT_EQ(std::filesystem::file_size(dir + "/after_restart.rfm"),
            std::filesystem::file_size(dir + "/before_kill.rfm"));
  EXPECT_TRUE(waitFor(walls, 10.0)) << "the resumed map is not published";

  // Mapping goes on from the resumed map.
  world.paused_ = false;
  EXPECT_TRUE(waitFor([&] { return stats.processed() > 80; }, 30.0));
  EXPECT_TRUE(walls());
  world.stop();
  kill(node, SIGINT);
  EXPECT_EQ(waitpid(node, &status, 0), node);
  if (!HasFailure()) std::filesystem::remove_all(dir);
}

TEST(ExtentLimit, AMapAtItsLimitDropsScansAndSaysSo) {
  char dir_template[] = "/tmp/rfm_extent_test_XXXXXX";
  ASSERT_NE(mkdtemp(dir_template), nullptr);
  const std::string dir = dir_template;
  constexpr double kLimit = 30.0;  // the active region alone spans 29.6 m, with its tiles

  ros::NodeHandle nh;
  MapCopy map;
  std::mutex mutex;
  bool reported = false;
  uint64_t beyond = 0;
  std::string extent;
  ros::AsyncSpinner spinner(2);
  auto on_diagnostics = [&](const diagnostic_msgs::DiagnosticArrayConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& status : msg->status) {
      if (status.message.find("map extent limit reached") != std::string::npos &&
          status.level == diagnostic_msgs::DiagnosticStatus::ERROR) {
        reported = true;
      }
      for (const auto& kv : status.values) {
        if (kv.key == "Scans dropped beyond the map extent limit (total)")
          beyond = std::strtoull(kv.value.c_str(), nullptr, 10);
        if (kv.key == "Map extent (m)") extent = kv.value;
      }
    }
  };
  std::vector<ros::Subscriber> subs = {
      nh.subscribe("/rfm/map", 5, &MapCopy::onMap, &map),
      nh.subscribe("/rfm/map_updates", 50, &MapCopy::onUpdate, &map),
      nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 20, on_diagnostics)};
  spinner.start();
  RoomWorld world(nh);
  // Out of the room to x = 8 and back to -8: the map the drive could make reaches 30 m on the
  // way back, at x = -2.4.
  world.half_range_ = 8.0;
  const pid_t node = startNode(dir, 1, "_max_map_extent:=" + std::to_string(kLimit));
  ASSERT_GT(node, 0);
  ASSERT_TRUE(waitFor([&] { return world.connected(); }, 30.0)) << "see " << dir << "/node_1.log";
  world.start();
  EXPECT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return reported && beyond > 0;
      },
      90.0))
      << "no extent limit reported; map extent " << extent;
  const nav_msgs::OccupancyGrid grid = map.copy();
  EXPECT_GT(grid.info.width, 0u);
  EXPECT_LE(grid.info.width * grid.info.resolution, kLimit + 1e-3);
  EXPECT_LE(grid.info.height * grid.info.resolution, kLimit + 1e-3);
  world.stop();
  kill(node, SIGINT);
  int status = 0;
  EXPECT_EQ(waitpid(node, &status, 0), node);
  if (!HasFailure()) std::filesystem::remove_all(dir);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rfm_restart_test");
  return RUN_ALL_TESTS();
}
