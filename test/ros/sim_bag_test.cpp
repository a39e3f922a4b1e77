// The live node fed by a simulated bag on simulated time: rfm_sim writes the test scene
// (glass_and_pedestrian.yaml: a framed glass pane in the north wall, a pedestrian walking past
// the robot and leaving) and the test replays its scans and transforms in the bag's order with
// /clock at each message's time, as `rosbag play --clock` does, but never more than a few scans
// ahead of the node's labels: what the node sees is the whole bag, however loaded the machine
// (a real-time replay loses scans in the subscriber queues of a starved node, and so its MOTION
// labels). Checks that /rfm/map (kept current with /rfm/map_updates) has the pane occupied and
// the pedestrian's path free, and that the node labelled the pedestrian's beams MOTION on the way.
// Every wait is a condition with a deadline, never a fixed sleep.
#include "map_copy.h"
#include "reflectance_field_map/RayLabels.h"
#include "reflectance_field_map/RfmStats.h"

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

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

// The node's last /rfm/stats: what it processed and dropped, to tell a scan the node lost from a
// label lost on its way to the test.
class LastStats {
 public:
  void onStats(const reflectance_field_map::RfmStatsConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    last_ = *msg;
    ++received_;
  }
  int received() {
    std::lock_guard<std::mutex> lock(mutex_);
    return received_;
  }
  reflectance_field_map::RfmStats last() {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_;
  }
  std::string summary() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::ostringstream text;
    text << "the node processed " << last_.scans_processed << " scans and dropped "
         << last_.scans_dropped;
    return text.str();
  }

 private:
  std::mutex mutex_;
  reflectance_field_map::RfmStats last_;
  int received_ = 0;
};

// Publishes a bag's scans and transforms in order, /clock at each message's time, each scan only
// once the node has labelled all but kScansAhead of the scans before it (their transforms come
// a message or two later, so the node cannot label the newest ones yet).
class PacedReplay {
 public:
  static constexpr int kScansAhead = 6;

  PacedReplay(ros::NodeHandle& nh, const std::vector<std::string>& scan_topics) {
    clock_ = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
    for (const std::string& topic : scan_topics)
      publishers_[topic] = nh.advertise<sensor_msgs::LaserScan>(topic, 100);
    publishers_["/tf"] = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
    publishers_["/tf_static"] = nh.advertise<tf2_msgs::TFMessage>("/tf_static", 10, true);
  }

  std::vector<std::string> topics() const {
    std::vector<std::string> names;
    for (const auto& [topic, publisher] : publishers_)
      names.push_back(topic);
    return names;
  }

  // The node listens to every topic, /clock included.
  bool nodeSubscribed() const {
    return clock_.getNumSubscribers() > 0 &&
           std::all_of(publishers_.begin(), publishers_.end(),
                       [](const auto& entry) { return entry.second.getNumSubscribers() > 0; });
  }

  // Replays `bag_path`; `labelled` counts the scans the node has labelled so far. Returns an
  // error, or "" once every message went out.
  std::string play(const std::string& bag_path, const std::function<int()>& labelled) {
    rosbag::Bag bag(bag_path);
    rosbag::View view(bag, rosbag::TopicQuery(topics()));
    int scans_sent = 0;
    for (const rosbag::MessageInstance& message : view) {
      publishClock(message.getTime());
      const ros::Publisher& publisher = publishers_.at(message.getTopic());
      if (const auto scan = message.instantiate<sensor_msgs::LaserScan>()) {
        if (!waitFor([&] { return labelled() >= scans_sent - kScansAhead; }, 30.0)) {
          return "the node labelled " + std::to_string(labelled()) + " of the " +
                 std::to_string(scans_sent) + " scans sent";
        }
        publisher.publish(scan);
        ++scans_sent;
      } else if (const auto transforms = message.instantiate<tf2_msgs::TFMessage>()) {
        publisher.publish(transforms);
      }
      end_ = message.getTime();
    }
    return "";
  }

  // Simulated time runs on from the bag's end (10 ms steps, ten times faster than wall time),
  // so that the node's timers see the bag end.
  void runClockOn(double seconds) {
    for (double t = 0.0; t <= seconds; t += 0.01) {
      publishClock(end_ + ros::Duration(t));
      ros::WallDuration(0.001).sleep();  // the clock's tick
    }
  }

 private:
  void publishClock(const ros::Time& time) {
    rosgraph_msgs::Clock tick;
    tick.clock = time;
    clock_.publish(tick);
  }

  ros::Publisher clock_;
  std::map<std::string, ros::Publisher> publishers_;
  ros::Time end_;
};

TEST(SimulatedBag, PaneOccupiedAndPedestrianPathFree) {
  char dir_template[] = "/tmp/rfm_sim_bag_test_XXXXXX";
  ASSERT_NE(mkdtemp(dir_template), nullptr);
  const std::string dir = dir_template;
  const std::string bag = dir + "/scene.bag";
  const std::string simulate = std::string(RFM_SIM_BINARY) + " --scene " + RFM_TEST_SCENE +
                               " --out " + bag + " > " + dir + "/sim.log 2>&1";
  ASSERT_EQ(std::system(simulate.c_str()), 0) << simulate;

  ros::NodeHandle nh;
  PacedReplay replay(nh, {"/scan_front", "/scan_rear"});
  MapCopy map;
  LabelCounter labels;
  LastStats stats;
  ros::AsyncSpinner spinner(2);
  std::vector<ros::Subscriber> subs = {
      nh.subscribe("/rfm/map", 5, &MapCopy::onMap, &map),
      nh.subscribe("/rfm/map_updates", 50, &MapCopy::onUpdate, &map),
      nh.subscribe("/rfm/scan_front/labels", 500, &LabelCounter::onLabels, &labels),
      nh.subscribe("/rfm/scan_rear/labels", 500, &LabelCounter::onLabels, &labels),
      nh.subscribe("/rfm/stats", 10, &LastStats::onStats, &stats)};
  spinner.start();
  // Every subscription connected both ways before the bag plays: the node labels a topic's scans
  // only while someone listens to its labels.
  ASSERT_TRUE(waitFor(
      [&] {
        return replay.nodeSubscribed() &&
               std::all_of(subs.begin(), subs.end(),
                           [](const ros::Subscriber& sub) { return sub.getNumPublishers() > 0; });
      },
      30.0))
      << "rfm node did not come up";

  const std::string replay_error = replay.play(bag, [&] { return labels.scans(); });
  ASSERT_EQ(replay_error, "");
  replay.runClockOn(3.0);

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

  // Stats sent after the map's last change count every scan of the bag.
  const int stats_so_far = stats.received();
  EXPECT_TRUE(waitFor([&] { return stats.received() >= stats_so_far + 2; }, 10.0))
      << "no /rfm/stats";
  std::cout << "labels: " << labels.scans() << " scans, " << labels.motion() << " MOTION beams; "
            << stats.summary() << "\n";
  EXPECT_GT(labels.scans(), 1000) << stats.summary();
  EXPECT_GT(labels.motion(), 3000)
      << "MOTION labels over " << labels.scans() << " scans; " << stats.summary();

  // A scan's latency splits into the wait for its transform and the node's own work. Each
  // scan here arrives before the transform at its stamp, which comes a message later: every
  // scan waits.
  const reflectance_field_map::RfmStats last = stats.last();
  EXPECT_GT(last.tf_wait_ms_median, 0.0);
  EXPECT_GT(last.scan_work_ms_median, 0.0);
  EXPECT_LE(last.tf_wait_ms_max, last.scan_latency_ms_max);
  EXPECT_LE(last.scan_work_ms_max, last.scan_latency_ms_max);

  std::filesystem::remove_all(dir);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rfm_sim_bag_test");
  return RUN_ALL_TESTS();
}
