// rfm_carmen2bag end to end: the smallest real log of shared/data (orebro: 181 beams, every
// laser stamp 0, max-range codes at 32.76 m) and a small log written here with backward
// stamps, a rear laser and a malformed line; the bags are read back with rosbag.

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>
#include "../scratch_directory_test.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct RunResult {
  int code = -1;
  std::string output;  // stdout and stderr
};

RunResult run(const std::string& arguments) {
  const std::string command = std::string(RFM_CARMEN2BAG_EXE) + " " + arguments + " 2>&1";
  RunResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0)
    result.output.append(buffer, n);
  const int status = pclose(pipe);
  result.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

struct BagContents {
  std::vector<sensor_msgs::LaserScan> scans, rear_scans;
  std::vector<ros::Time> scan_bag_times;
  std::vector<geometry_msgs::TransformStamped> tf, tf_static;
  std::vector<nav_msgs::Odometry> odometry;
  std::map<std::string, int> per_topic;
  bool bag_times_ordered = true;
};

BagContents readBag(const std::string& path) {
  BagContents contents;
  rosbag::Bag bag(path);
  ros::Time previous;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    ++contents.per_topic[m.getTopic()];
    if (m.getTime() < previous) contents.bag_times_ordered = false;
    previous = m.getTime();
    if (auto scan = m.instantiate<sensor_msgs::LaserScan>()) {
      (m.getTopic() == "/scan_rear" ? contents.rear_scans : contents.scans).push_back(*scan);
      if (m.getTopic() == "/scan") contents.scan_bag_times.push_back(m.getTime());
    } else if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
      auto& into = m.getTopic() == "/tf_static" ? contents.tf_static : contents.tf;
      into.insert(into.end(), tf->transforms.begin(), tf->transforms.end());
    } else if (auto odom = m.instantiate<nav_msgs::Odometry>()) {
      contents.odometry.push_back(*odom);
    }
  }
  return contents;
}

class Carmen2Bag : public rfm_test::ScratchDirectoryTest {};

TEST_F(Carmen2Bag, SmallestRealLog) {
  const std::string log = RFM_SHARED_DATA_DIR "/real/orebro-corrected.log.gz";
  if (!fs::is_regular_file(log)) GTEST_SKIP() << log << " is not there";
  const RunResult result = run(log + " " + path("orebro.bag"));
  ASSERT_EQ(result.code, 0) << result.output;
  // What was done with the clock is said: every laser stamp of this log is 0.
  EXPECT_NE(result.output.find("stamps are unusable"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("synthesised"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("max-range code"), std::string::npos) << result.output;

  const BagContents bag = readBag(path("orebro.bag"));
  EXPECT_TRUE(bag.bag_times_ordered);
  ASSERT_EQ(bag.scans.size(), 237u);  // the log's FLASER lines
  EXPECT_TRUE(bag.rear_scans.empty());
  EXPECT_EQ(bag.tf.size(), 237u);
  EXPECT_EQ(bag.odometry.size(), 255u);  // its ODOM lines
  ASSERT_EQ(bag.tf_static.size(), 1u);
  EXPECT_EQ(bag.tf_static[0].header.frame_id, "base_link");
  EXPECT_EQ(bag.tf_static[0].child_frame_id, "laser");
  EXPECT_DOUBLE_EQ(bag.tf_static[0].transform.translation.x, 0.0);
  EXPECT_DOUBLE_EQ(bag.tf_static[0].transform.rotation.w, 1.0);

  size_t no_return = 0, returns = 0;
  double previous = 0.0;
  for (size_t i = 0; i < bag.scans.size(); ++i) {
    const auto& scan = bag.scans[i];
    EXPECT_EQ(scan.header.frame_id, "laser");
    EXPECT_EQ(scan.header.seq, i);
    EXPECT_GT(scan.header.stamp.toSec(), previous) << "scan " << i;  // strictly monotonic
    previous = scan.header.stamp.toSec();
    EXPECT_EQ(bag.scan_bag_times[i], scan.header.stamp);
    ASSERT_EQ(scan.ranges.size(), 181u);
    EXPECT_NEAR(scan.angle_min, -M_PI / 2, 1e-6);
    EXPECT_NEAR(scan.angle_increment, M_PI / 180, 1e-7);
    EXPECT_NEAR(scan.angle_max, M_PI / 2, 1e-5);
    EXPECT_GT(scan.range_max, 32.63f);  // the largest real return
    EXPECT_LE(scan.range_max, 32.759f);
    for (const float r : scan.ranges) {
      if (std::isinf(r)) {
        EXPECT_GT(r, 0.0f);
        ++no_return;
      } else if (std::isfinite(r)) {
        EXPECT_LT(r, scan.range_max);
        ++returns;
      }
    }
    // The odom -> base_link of each scan at its stamp.
    EXPECT_EQ(bag.tf[i].header.stamp, scan.header.stamp);
    EXPECT_EQ(bag.tf[i].header.frame_id, "odom");
    EXPECT_EQ(bag.tf[i].child_frame_id, "base_link");
  }
  EXPECT_EQ(no_return, 968u);  // readings of 32.759, 32.763, 32.765 and 32.767 m
  EXPECT_GT(returns, 237u * 181u - 968u - 500u);
  // The first scan's corrected pose: 0.255856 0.0163473 0.618883.
  EXPECT_NEAR(bag.tf[0].transform.translation.x, 0.255856, 1e-9);
  EXPECT_NEAR(bag.tf[0].transform.translation.y, 0.0163473, 1e-9);
  EXPECT_NEAR(2 * std::atan2(bag.tf[0].transform.rotation.z, bag.tf[0].transform.rotation.w),
              0.618883, 1e-9);
  for (size_t i = 1; i < bag.odometry.size(); ++i) {
    EXPECT_GE(bag.odometry[i].header.stamp, bag.odometry[i - 1].header.stamp);
  }
}

TEST_F(Carmen2Bag, QuirkyLogWithRearLaser) {
  std::ofstream log(path("quirky.log"));
  log << "# message formats defined: PARAM SYNC ODOM FLASER RLASER\n";
  const double stamps[] = {50.0, 51.0, 52.0, 51.5, 53.5, 54.5, 55.5, 56.5, 57.5, 58.5, 59.5, 60.5};
  for (int i = 0; i < 12; ++i) {
    std::string ranges;
    for (int b = 0; b < 361; ++b)
      ranges += b == 7 ? " 81.91" : " 4.25";
    const std::string pose = std::to_string(0.5 * i) + " 0 0 " + std::to_string(0.5 * i) + " 0 0 ";
    log << "FLASER 361" << ranges << " " << pose << stamps[i] << " host " << stamps[i] << "\n";
    const std::string rear_pose = std::to_string(0.5 * i - 0.4) + " 0 3.14159265 " +
                                  std::to_string(0.5 * i - 0.4) + " 0 3.14159265 ";
    log << "RLASER 361" << ranges << " " << rear_pose << stamps[i] + 0.1 << " host "
        << stamps[i] + 0.1 << "\n";
    log << "ODOM 0 0 0 0 0 0 " << stamps[i] + 0.2 << " host " << stamps[i] + 0.2 << "\n";
  }
  log << "FLASER 361 1 2 3\n";  // malformed: reported, not converted
  log.close();

  const RunResult result = run(path("quirky.log") + " " + path("quirky.bag"));
  ASSERT_EQ(result.code, 0) << result.output;
  EXPECT_NE(result.output.find("1 malformed lines are not converted"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("line 38: FLASER: num_readings is 361"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("1 backwards"), std::string::npos) << result.output;
  const BagContents bag = readBag(path("quirky.bag"));
  EXPECT_TRUE(bag.bag_times_ordered);
  ASSERT_EQ(bag.scans.size(), 12u);
  ASSERT_EQ(bag.rear_scans.size(), 12u);
  EXPECT_EQ(bag.tf.size(), 24u);
  EXPECT_EQ(bag.odometry.size(), 12u);
  ASSERT_EQ(bag.tf_static.size(), 2u);
  EXPECT_EQ(bag.tf_static[1].child_frame_id, "laser_rear");
  // -0.4 m behind the front laser where the robot was 0.1 s before (it moves 0.5 m/s).
  EXPECT_NEAR(bag.tf_static[1].transform.translation.x, -0.4, 0.06);
  EXPECT_NEAR(std::abs(bag.tf_static[1].transform.rotation.z), 1.0, 1e-6);  // facing back
  for (size_t i = 1; i < bag.scans.size(); ++i) {
    EXPECT_GT(bag.scans[i].header.stamp, bag.scans[i - 1].header.stamp);
    EXPECT_GT(bag.rear_scans[i].header.stamp, bag.scans[i - 1].header.stamp);
  }
  EXPECT_EQ(bag.rear_scans[0].header.frame_id, "laser_rear");
  EXPECT_NEAR(bag.scans[0].angle_increment, M_PI / 360, 1e-7);
  EXPECT_TRUE(std::isinf(bag.scans[0].ranges[7]));
  EXPECT_FLOAT_EQ(bag.scans[0].ranges[8], 4.25f);
}

TEST_F(Carmen2Bag, ClearErrors) {
  RunResult result = run(path("absent.log") + " " + path("out.bag"));
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("cannot read"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(path("out.bag")));

  std::ofstream(path("nothing.log")) << "ODOM 0 0 0 0 0 0 1 h 1\nNEFF 3\n";
  result = run(path("nothing.log") + " " + path("out.bag"));
  EXPECT_EQ(result.code, 1);
  EXPECT_NE(result.output.find("no FLASER, RLASER or ROBOTLASER1 line"), std::string::npos)
      << result.output;

  // A gzip file cut short.
  const std::string log = RFM_SHARED_DATA_DIR "/real/orebro-corrected.log.gz";
  if (fs::is_regular_file(log)) {
    std::ifstream in(log, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(path("cut.log.gz"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    result = run(path("cut.log.gz") + " " + path("out.bag"));
    EXPECT_EQ(result.code, 1);
    EXPECT_NE(result.output.find("cut.log.gz"), std::string::npos) << result.output;
  }

  result = run(path("a.log"));
  EXPECT_EQ(result.code, 2);
  EXPECT_NE(result.output.find("Usage"), std::string::npos) << result.output;
  result = run(path("a.log") + " " + path("b.bag") + " --max-range -3");
  EXPECT_EQ(result.code, 2);
  EXPECT_NE(result.output.find("--max-range: '-3' is not a positive number"), std::string::npos)
      << result.output;
  result = run("--help");
  EXPECT_EQ(result.code, 0);
  EXPECT_NE(result.output.find("--fov"), std::string::npos);
}

}  // namespace
