// Round trip through the bag writer: topics, counts, TF rate, latched static TF, truth per beam.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <reflectance_field_map/RayTruth.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <map>

#include "reflectance_field_map/sim/scene.h"
#include "sim_bag_writer.h"

namespace {

const char* kScene = R"(
name: bag_test
duration: 2.0
walls:
  - {type: polyline, material: diffuse, closed: true, points: [[-6, -6], [6, -6], [6, 6], [-6, 6]]}
  - {type: segment, material: glass, points: [[2, -3], [2, 3]]}
people:
  - {speed: 1.0, waypoints: [[0, -2], [0, 2]]}
robot:
  start_delay: 0.2
  waypoints: [[-3, 0], [1, 0]]
)";

class SimBagTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/rfm_sim_bag_testXXXXXX";
    const int fd = mkstemp(pattern);
    ASSERT_GE(fd, 0);
    close(fd);
    path_ = std::string(pattern) + ".bag";
    std::remove(pattern);
    scene_ = rfm::sim::parseScene(kScene, "bag_test");
    summary_ = rfm::tools::writeSimulationBag(scene_, 3, path_);
  }
  void TearDown() override { std::remove(path_.c_str()); }
  std::string path_;
  rfm::sim::Scene scene_;
  rfm::sim::SimulationSummary summary_;
};

TEST_F(SimBagTest, TopicsCountsRatesAndTruthReadBack) {
  rosbag::Bag bag(path_, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::map<std::string, int> counts;
  std::map<std::string, std::string> types;
  std::vector<double> tf_times;
  std::map<std::pair<std::string, std::uint64_t>, std::size_t> scan_beams, truth_beams;
  ros::Time first = ros::TIME_MAX;
  bool static_latched = false;
  for (const rosbag::MessageInstance& m : view) {
    ++counts[m.getTopic()];
    types[m.getTopic()] = m.getDataType();
    first = std::min(first, m.getTime());
    if (m.getTopic() == "/tf") {
      const auto tf = m.instantiate<tf2_msgs::TFMessage>();
      ASSERT_EQ(tf->transforms.size(), 1u);
      EXPECT_EQ(tf->transforms[0].header.frame_id, "odom");
      EXPECT_EQ(tf->transforms[0].child_frame_id, "base_link");
      EXPECT_EQ(tf->transforms[0].header.stamp, m.getTime());
      tf_times.push_back(m.getTime().toSec());
    } else if (m.getTopic() == "/tf_static") {
      const auto tf = m.instantiate<tf2_msgs::TFMessage>();
      ASSERT_EQ(tf->transforms.size(), 2u);
      EXPECT_EQ(tf->transforms[0].child_frame_id, "laser_front");
      EXPECT_EQ(tf->transforms[1].child_frame_id, "laser_rear");
      EXPECT_NEAR(tf->transforms[1].transform.translation.x, -0.35, 1e-12);
      EXPECT_NEAR(tf->transforms[1].transform.rotation.z, 1.0, 1e-12);  // yaw pi
      const auto header = m.getConnectionHeader();
      static_latched = header && header->count("latching") && header->at("latching") == "1";
    } else if (m.getTopic() == "/scan_front" || m.getTopic() == "/scan_rear") {
      const auto scan = m.instantiate<sensor_msgs::LaserScan>();
      EXPECT_EQ(scan->header.frame_id,
                m.getTopic() == "/scan_front" ? "laser_front" : "laser_rear");
      EXPECT_EQ(scan->header.stamp, m.getTime());
      EXPECT_NEAR(scan->angle_min, -135.0 * M_PI / 180.0, 1e-6);
      EXPECT_NEAR(scan->angle_max, 135.0 * M_PI / 180.0, 1e-6);
      EXPECT_FLOAT_EQ(scan->range_max, 30.0f);
      scan_beams[{m.getTopic(), scan->header.stamp.toNSec()}] = scan->ranges.size();
    } else if (m.getTopic() == "/sim/ray_truth") {
      const auto truth = m.instantiate<reflectance_field_map::RayTruth>();
      truth_beams[{truth->scan_topic, truth->header.stamp.toNSec()}] = truth->classes.size();
    } else if (m.getTopic() == "/odom") {
      const auto odom = m.instantiate<nav_msgs::Odometry>();
      EXPECT_EQ(odom->child_frame_id, "base_link");
    }
  }
  EXPECT_EQ(types["/sim/ray_truth"], "reflectance_field_map/RayTruth");
  EXPECT_EQ(types["/scan_front"], "sensor_msgs/LaserScan");
  EXPECT_EQ(types["/odom"], "nav_msgs/Odometry");
  EXPECT_EQ(counts["/scan_front"], 81);  // 40 Hz over [0, 2] s inclusive
  EXPECT_EQ(counts["/scan_rear"], 80);   // offset by half a period
  EXPECT_EQ(counts["/sim/ray_truth"], 161);
  EXPECT_EQ(counts["/tf_static"], 1);
  EXPECT_TRUE(static_latched);
  EXPECT_GE(counts["/odom"], 100);
  EXPECT_NEAR(first.toSec(), 1000.0, 1e-9);  // bag time starts at 1000 s, not 0

  // TF rate: at least 50 Hz over the span, and no gap longer than 20 ms.
  ASSERT_GT(tf_times.size(), 2u);
  const double span = tf_times.back() - tf_times.front();
  EXPECT_GE((tf_times.size() - 1) / span, 50.0);
  for (std::size_t i = 1; i < tf_times.size(); ++i)
    EXPECT_LE(tf_times[i] - tf_times[i - 1], 0.02 + 1e-9);

  // One truth message per scan, with the same stamp and 1081 classes.
  EXPECT_EQ(truth_beams.size(), scan_beams.size());
  for (const auto& [key, beams] : scan_beams) {
    ASSERT_TRUE(truth_beams.count(key)) << key.first << " " << key.second;
    EXPECT_EQ(truth_beams[key], beams);
    EXPECT_EQ(beams, 1081u);
  }
  EXPECT_EQ(summary_.scans, 161u);
}

TEST(SimBagWriterTest, UnwritableOutputThrows) {
  const rfm::sim::Scene scene = rfm::sim::parseScene(kScene, "bag_test");
  EXPECT_THROW(rfm::tools::writeSimulationBag(scene, 1, "/nonexistent_dir/x.bag"),
               rosbag::BagException);
}

}  // namespace
