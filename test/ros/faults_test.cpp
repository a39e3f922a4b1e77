// rfm_node (faults_node.test, simulated time) driven by a robot in a room (room_world.h) while
// the faults a wheelchair meets are injected one after the other, each a test:
//   transforms late, transforms missing for a while, one lidar silent and back, a stale scan,
//   a 1 km pose jump, a burst of scans faster than the node maps them, a corrupted saved state,
//   and ROS time jumping back (a looping bag).
// The test owns /clock, so simulated time is exactly what it publishes. Each fault must be
// counted under its own reason, must not reset or grow the map (except the clock jump, which
// must reset it), and mapping must go on afterwards. Throughout, every scan published is
// accounted for: processed or dropped (the node's diagnostics). The node's TF listener is also
// run on its own against the room's transforms. Every wait is a condition with a deadline.
#include "map_copy.h"
#include "reflectance_field_map/LoadMap.h"
#include "reflectance_field_map/RfmStats.h"
#include "reflectance_field_map/SaveMap.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/state_file.h"
#include "reflectance_field_map/ros/transform_listener_thread.h"
#include "room_world.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_ros/buffer.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>

namespace {

using rfm_test::MapCopy;
using rfm_test::RoomWorld;
using rfm_test::waitFor;

// Simulated time that runs with the wall clock from 1000 s and can be sent back.
class SimClock {
 public:
  explicit SimClock(ros::NodeHandle& nh) : pub_(nh.advertise<rosgraph_msgs::Clock>("/clock", 10)) {}
  ~SimClock() { stop(); }

  void start() {
    running_ = true;
    thread_ = std::thread([this] {
      ros::WallTime last = ros::WallTime::now();
      while (running_ && ros::ok()) {
        ros::WallDuration(0.005).sleep();  // the clock's tick
        const ros::WallTime wall = ros::WallTime::now();
        rosgraph_msgs::Clock msg;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          now_ += ros::Duration((wall - last).toSec());
          msg.clock = now_;
        }
        last = wall;
        pub_.publish(msg);
      }
    });
  }
  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }
  ros::Time now() {
    std::lock_guard<std::mutex> lock(mutex_);
    return now_;
  }
  void jumpBack(double seconds) {
    std::lock_guard<std::mutex> lock(mutex_);
    now_ -= ros::Duration(seconds);
  }

 private:
  ros::Publisher pub_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::mutex mutex_;
  ros::Time now_{1000.0};
};

struct Status {
  int level = -1;
  std::string message;
  std::map<std::string, std::string> values;
};

class Node {
 public:
  explicit Node(ros::NodeHandle& nh) {
    subs_.push_back(nh.subscribe("/rfm/map", 5, &MapCopy::onMap, &map));
    subs_.push_back(nh.subscribe("/rfm/map", 5, &Node::onMap, this));
    subs_.push_back(nh.subscribe("/rfm/map_updates", 50, &MapCopy::onUpdate, &map));
    subs_.push_back(nh.subscribe("/rfm/stats", 10, &Node::onStats, this));
    subs_.push_back(nh.subscribe("/diagnostics", 50, &Node::onDiagnostics, this));
  }

  // A reset publishes a map with nothing occupied.
  void onMap(const nav_msgs::OccupancyGridConstPtr& msg) {
    if (std::count(msg->data.begin(), msg->data.end(), 100) == 0) ++empty_maps;
  }
  void onStats(const reflectance_field_map::RfmStatsConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_ = *msg;
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArrayConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& status : msg->status) {
      Status& mine = statuses_[status.name];
      messages_seen_.insert(status.message);
      mine.level = status.level;
      mine.message = status.message;
      for (const auto& kv : status.values)
        mine.values[kv.key] = kv.value;
    }
  }

  // The status whose name ends with `name` ("rfm: Mapper" ends with "Mapper").
  Status status(const std::string& name) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [full, status] : statuses_) {
      if (full.size() >= name.size() &&
          full.compare(full.size() - name.size(), name.size(), name) == 0)
        return status;
    }
    return {};
  }
  // A counter a status reports (0 when absent).
  uint64_t value(const std::string& name, const std::string& key) {
    const Status s = status(name);
    const auto it = s.values.find(key);
    return it == s.values.end() ? 0 : std::strtoull(it->second.c_str(), nullptr, 10);
  }
  // Whether any status ever said something containing `text`.
  bool said(const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const std::string& message : messages_seen_) {
      if (message.find(text) != std::string::npos) return true;
    }
    return false;
  }
  std::string describe() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::ostringstream out;
    out << "stats: processed " << stats_.scans_processed << ", dropped " << stats_.scans_dropped;
    for (const auto& [name, status] : statuses_) {
      out << "\n  " << name << " [" << status.level << "] " << status.message;
      for (const auto& [key, value] : status.values)
        out << " | " << key << "=" << value;
    }
    return out.str();
  }

  MapCopy map;
  std::atomic<int> empty_maps{0};

 private:
  std::vector<ros::Subscriber> subs_;
  std::mutex mutex_;
  reflectance_field_map::RfmStats stats_;
  std::map<std::string, Status> statuses_;
  std::set<std::string> messages_seen_;
};

SimClock* sim_clock = nullptr;
RoomWorld* world = nullptr;
Node* node = nullptr;

// The room's walls as the map shows them.
bool wallsMapped() {
  return node->map.occupiedNear(0.0, rfm_test::kRoomHalfY) &&
         node->map.occupiedNear(0.0, -rfm_test::kRoomHalfY) &&
         node->map.occupiedNear(rfm_test::kRoomHalfX, 0.0);
}

// Every scan published so far is processed or dropped, as the node's /diagnostics (a wall
// timer's, so they keep coming through a clock jump back) count them.
uint64_t processed() {
  return node->value("Mapper", "Scans processed");
}

uint64_t dropped() {
  return node->value("Scan input", "Scans dropped (total)") +
         node->value("Scan input", "Scans lost in subscriber queues (total)");
}

bool allAccounted() {
  return processed() + dropped() == world->published();
}

// Pauses the world and waits until the node has dealt with every scan it was sent.
void pauseAndSettle() {
  world->paused_ = true;
  // The odometry a little past the last scan, so that no scan waits for a transform.
  ASSERT_TRUE(
      waitFor([] { return sim_clock->now() > world->lastStamp() + ros::Duration(0.05); }, 5.0));
  world->publishOdometry(sim_clock->now());
  ASSERT_TRUE(waitFor(allAccounted, 20.0))
      << world->published() << " published; " << node->describe();
}

// Mapping goes on: `scans` more processed within the deadline.
bool mapsOn(uint64_t scans = 40) {
  const uint64_t before = processed();
  return waitFor([&] { return processed() >= before + scans; }, 15.0);
}

TEST(Faults, MapsTheRoomWithoutDrops) {
  ASSERT_TRUE(waitFor(wallsMapped, 30.0)) << node->describe();
  pauseAndSettle();
  EXPECT_EQ(dropped(), 0u) << node->describe();
  EXPECT_GT(processed(), 0u);
  world->paused_ = false;
}

// Odometry 150 ms late: scans wait for it in the TF queue (20 per topic) and none is lost.
TEST(Faults, LateTransformsAreWaitedFor) {
  const uint64_t dropped_before = dropped();
  world->tf_delay_ = 0.15;
  EXPECT_TRUE(mapsOn(80)) << node->describe();
  world->tf_delay_ = 0.0;
  pauseAndSettle();
  EXPECT_EQ(dropped(), dropped_before) << node->describe();
  world->paused_ = false;
}

// Two seconds without odometry: the scans that waited longer than the queue holds are dropped
// as without a transform (and diagnostics say so), the others are placed once it returns, and
// mapping goes on without a reset.
TEST(Faults, ATransformGapDropsItsScansAndMappingGoesOn) {
  const uint64_t without_tf = node->value("TF", "Scans without transform (total)");
  world->tf_missing_ = true;
  const ros::Time gap_end = sim_clock->now() + ros::Duration(2.0);
  ASSERT_TRUE(waitFor([&] { return sim_clock->now() > gap_end; }, 10.0));
  world->tf_missing_ = false;
  EXPECT_TRUE(mapsOn()) << node->describe();
  EXPECT_TRUE(waitFor(
      [&] { return node->value("TF", "Scans without transform (total)") > without_tf + 40; }, 10.0))
      << node->describe();
  pauseAndSettle();
  EXPECT_EQ(node->value("Mapper", "Time jumps (total)"), 0u);
  EXPECT_TRUE(wallsMapped());
  world->paused_ = false;
}

// The rear lidar stops for 3 s: its rate diagnostic turns ERROR, and OK again once it is back.
TEST(Faults, ASilentLidarIsReportedAndRecovers) {
  using diagnostic_msgs::DiagnosticStatus;
  ASSERT_TRUE(waitFor(
      [] { return node->status("Scan rate /scan_rear").level == DiagnosticStatus::OK; }, 10.0))
      << node->describe();
  world->rear_silent_ = true;
  EXPECT_TRUE(waitFor(
      [] { return node->status("Scan rate /scan_rear").level == DiagnosticStatus::ERROR; }, 10.0))
      << node->describe();
  EXPECT_EQ(node->status("Scan rate /scan_front").level, DiagnosticStatus::OK);
  world->rear_silent_ = false;
  EXPECT_TRUE(waitFor(
      [] { return node->status("Scan rate /scan_rear").level == DiagnosticStatus::OK; }, 15.0))
      << node->describe();
  EXPECT_TRUE(mapsOn());
}

// One scan stamped 5 s before the previous one on its topic: dropped and counted as stale, the
// map kept (a time jump, which resets the map, is ROS time going back, not one late scan).
TEST(Faults, AStaleScanIsDroppedAndTheMapKept) {
  pauseAndSettle();
  const int empty_maps = node->empty_maps;
  world->publishFront(world->lastStamp() - ros::Duration(5.0));
  EXPECT_TRUE(
      waitFor([] { return node->value("Scan input", "Stale scans dropped (total)") == 1; }, 10.0))
      << node->describe();
  EXPECT_TRUE(waitFor(allAccounted, 10.0)) << node->describe();
  EXPECT_TRUE(waitFor([] { return node->said("1 stale scans dropped"); }, 10.0))
      << node->describe();
  world->paused_ = false;
  EXPECT_TRUE(mapsOn());
  EXPECT_EQ(node->value("Mapper", "Time jumps (total)"), 0u);
  EXPECT_EQ(node->empty_maps, empty_maps) << "the map was reset";
  EXPECT_TRUE(wallsMapped());
}

// The odometry jumps 1 km for one second (a TF glitch): every scan of that second is dropped as
// a pose jump, the published map keeps its size, and mapping goes on where the robot is.
TEST(Faults, APoseJumpOfOneKilometreIsRejected) {
  pauseAndSettle();
  const nav_msgs::OccupancyGrid before = node->map.copy();
  const uint64_t jumps = node->value("Mapper", "Scans dropped at a pose jump (total)");
  const uint64_t jumped_before = world->jumpedScans();
  world->paused_ = false;
  world->odom_jump_x_ = 1000.0;
  const ros::Time glitch_end = sim_clock->now() + ros::Duration(1.0);
  ASSERT_TRUE(waitFor([&] { return sim_clock->now() > glitch_end; }, 10.0));
  world->odom_jump_x_ = 0.0;
  EXPECT_TRUE(mapsOn()) << node->describe();
  pauseAndSettle();
  const uint64_t jumped = world->jumpedScans() - jumped_before;
  EXPECT_GT(jumped, 40u);
  EXPECT_EQ(node->value("Mapper", "Scans dropped at a pose jump (total)"), jumps + jumped)
      << node->describe();
  EXPECT_TRUE(node->said("dropped at a pose jump (last ")) << node->describe();
  const nav_msgs::OccupancyGrid after = node->map.copy();
  EXPECT_EQ(after.info.width, before.info.width);
  EXPECT_EQ(after.info.height, before.info.height);
  EXPECT_LT(after.info.width * after.info.resolution, 60.0);
  EXPECT_EQ(node->value("Mapper", "Time jumps (total)"), 0u);
  world->paused_ = false;
}

// 600 scans of 20000 beams at once (more than the node's subscriber queue holds, 400), far
// faster than the node maps them: the queues stay bounded, and every one is either processed or
// counted as dropped.
TEST(Faults, AScanBurstIsBoundedAndCounted) {
  pauseAndSettle();
  const uint64_t dropped_before = dropped(), processed_before = processed();
  const ros::Time first = world->lastStamp();
  ASSERT_TRUE(waitFor([&] { return sim_clock->now() > first + ros::Duration(0.4); }, 5.0));
  world->publishOdometry(sim_clock->now());
  constexpr int kBurst = 600;
  for (int i = 1; i <= kBurst; ++i)
    world->publishFront(first + ros::Duration(0.001 * i), 20000);
  world->paused_ = false;  // the next scans reveal any burst scans lost at the end of the queue
  pauseAndSettle();
  EXPECT_GT(dropped(), dropped_before) << "the burst never overflowed a queue";
  EXPECT_GT(processed(), processed_before);
  EXPECT_GT(node->value("Scan input", "Scans lost in subscriber queues (total)") +
                node->value("Scan input", "TF queue overflows (total)"),
            0u)
      << node->describe();
  world->paused_ = false;
  EXPECT_TRUE(mapsOn());
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

// A saved state with flipped bytes, a truncated one and a foreign file are each refused with
// the reason, and the running map is exactly as it was: saved again after the refusals, it gives
// the same files. The intact file still loads.
TEST(Faults, ACorruptedStateIsRefusedAndTheMapUntouched) {
  ros::NodeHandle nh;
  ros::ServiceClient save = nh.serviceClient<reflectance_field_map::SaveMap>("/rfm/save_map");
  ros::ServiceClient load = nh.serviceClient<reflectance_field_map::LoadMap>("/rfm/load_map");
  ASSERT_TRUE(save.waitForExistence(ros::Duration(10.0)));
  std::string dir;
  ASSERT_TRUE(nh.getParam("/rfm/map_directory", dir));
  pauseAndSettle();
  reflectance_field_map::SaveMap saved;
  saved.request.path = "good";
  ASSERT_TRUE(save.call(saved));
  ASSERT_TRUE(saved.response.success) << saved.response.message;
  const std::string good = readFile(dir + "/good.rfm");
  ASSERT_GT(good.size(), 1000u);

  std::string flipped = good;
  for (size_t at = good.size() / 3; at < good.size() / 3 + 200; ++at)
    flipped[at] = static_cast<char>(flipped[at] ^ 0x5a);
  std::ofstream(dir + "/flipped.rfm", std::ios::binary) << flipped;
  std::ofstream(dir + "/truncated.rfm", std::ios::binary) << good.substr(0, good.size() / 2);
  std::ofstream(dir + "/foreign.rfm", std::ios::binary) << std::string(4096, '\x7f');
  for (const auto& [name, reason] : {std::pair<std::string, std::string>{"flipped", "checksum"},
                                     {"truncated", "truncated"},
                                     {"foreign", "not a saved rfm state"}}) {
    reflectance_field_map::LoadMap bad;
    bad.request.path = name;
    ASSERT_TRUE(load.call(bad));
    EXPECT_FALSE(bad.response.success) << name;
    EXPECT_NE(bad.response.message.find(reason), std::string::npos) << bad.response.message;
    EXPECT_NE(bad.response.message.find("unchanged"), std::string::npos) << bad.response.message;
  }
  reflectance_field_map::SaveMap again;
  again.request.path = "after_refusals";
  ASSERT_TRUE(save.call(again));
  ASSERT_TRUE(again.response.success) << again.response.message;
  EXPECT_EQ(readFile(dir + "/after_refusals.pgm"), readFile(dir + "/good.pgm"));
  EXPECT_EQ(readFile(dir + "/after_refusals.rfm"), good);

  reflectance_field_map::LoadMap intact;
  intact.request.path = "good";
  ASSERT_TRUE(load.call(intact));
  EXPECT_TRUE(intact.response.success) << intact.response.message;
  world->paused_ = false;
  EXPECT_TRUE(mapsOn());
}

// A state whose checksum is right but whose map spans 3.2 km (two tiles 1000 tiles apart: its
// window would take the node's memory) is refused by max_map_extent before it replaces
// anything.
TEST(Faults, AStateBeyondTheMapExtentLimitIsRefused) {
  ros::NodeHandle nh;
  ros::ServiceClient load = nh.serviceClient<reflectance_field_map::LoadMap>("/rfm/load_map");
  ASSERT_TRUE(load.waitForExistence(ros::Duration(10.0)));
  std::string dir;
  ASSERT_TRUE(nh.getParam("/rfm/map_directory", dir));
  rfm::GlobalMap2D far_apart;
  far_apart.set({0, 0}, rfm::CellClass::kStatic);
  far_apart.set({1000 * far_apart.tileCells(), 0}, rfm::CellClass::kStatic);
  std::ostringstream payload;
  const uint32_t mapper_magic = 0x52464d53, field_magic = 0x52464d31;
  payload.write(reinterpret_cast<const char*>(&mapper_magic), 4);
  far_apart.write(payload);
  const int32_t bins = 180, tile_cells = 16;
  const double resolution = 0.05;
  const uint64_t archived = 0;
  payload.write(reinterpret_cast<const char*>(&field_magic), 4);
  payload.write(reinterpret_cast<const char*>(&bins), 4);
  payload.write(reinterpret_cast<const char*>(&tile_cells), 4);
  payload.write(reinterpret_cast<const char*>(&resolution), 8);
  payload.write(reinterpret_cast<const char*>(&archived), 8);
  {
    std::ofstream file(dir + "/far_apart.rfm", std::ios::binary);
    rfm::writeStateFile(file, payload.str());
  }
  pauseAndSettle();
  const int empty_maps = node->empty_maps;
  reflectance_field_map::LoadMap far;
  far.request.path = "far_apart";
  ASSERT_TRUE(load.call(far));
  EXPECT_FALSE(far.response.success);
  EXPECT_NE(far.response.message.find("more than max_map_extent 400 m"), std::string::npos)
      << far.response.message;
  world->paused_ = false;
  EXPECT_TRUE(mapsOn());
  EXPECT_EQ(node->empty_maps, empty_maps);
  EXPECT_LT(node->map.copy().info.width * node->map.copy().info.resolution, 60.0);
}

// ROS time jumps back 20 s (a bag looping with --clock): the map is reset, diagnostics say the
// clock jumped, and mapping starts again.
TEST(Faults, AClockJumpBackResetsTheMap) {
  ASSERT_TRUE(waitFor(wallsMapped, 10.0));
  const int empty_maps = node->empty_maps;
  sim_clock->jumpBack(20.0);
  EXPECT_TRUE(waitFor([] { return node->value("Mapper", "Time jumps (total)") == 1; }, 10.0))
      << node->describe();
  EXPECT_TRUE(waitFor([&] { return node->empty_maps > empty_maps; }, 10.0))
      << "no reset map published";
  EXPECT_TRUE(waitFor([] { return node->said("ROS time jumped back by "); }, 10.0))
      << node->describe();
  EXPECT_TRUE(mapsOn()) << node->describe();
  EXPECT_TRUE(waitFor(wallsMapped, 30.0)) << node->describe();
  pauseAndSettle();
}

}  // namespace

// The node's TF listener: a buffer of its own fills from the room's /tf and latched /tf_static
// on the listener's thread (the test's spinner never serves its queue), and going out of scope
// joins that thread (a hang would run into the test's time limit) and keeps what it received.
TEST(TransformListenerThread, FillsItsBufferFromTfAndTfStatic) {
  world->paused_ = false;  // odometry on /tf again
  tf2_ros::Buffer buffer;
  {
    ros::NodeHandle nh;
    rfm::ros_glue::TransformListenerThread listener(buffer, nh);
    EXPECT_TRUE(
        waitFor([&] { return buffer.canTransform("odom", "laser_rear", ros::Time(0)); }, 10.0))
        << buffer.allFramesAsString();
  }
  EXPECT_TRUE(buffer.canTransform("odom", "laser_rear", ros::Time(0)));
  pauseAndSettle();
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rfm_faults_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  SimClock clock(nh);
  clock.start();
  RoomWorld room(nh, [&clock] { return clock.now(); });
  Node observed(nh);
  sim_clock = &clock;
  world = &room;
  node = &observed;
  if (!waitFor([&] { return room.connected(); }, 30.0)) {
    ADD_FAILURE() << "rfm node did not subscribe";
    return 1;
  }
  room.start();
  const int result = RUN_ALL_TESTS();
  room.stop();
  clock.stop();
  std::string dir;
  if (nh.getParam("/rfm/map_directory", dir)) std::filesystem::remove_all(dir);
  return result;
}
