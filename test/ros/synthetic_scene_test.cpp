// The live mapper (rfm_node or the RfmNodelet, per .test file) fed with synthetic scans and TF
// published from this test: a robot drives past a glass pane set in a wall, with a diffuse wall
// behind the glass. The pane returns the laser only near its normal.
//
// Checks, in order (one scenario, driven once):
//   1. /rfm/map (+ /rfm/map_updates) has the pane and the wall occupied;
//   2. /rfm/scan_front/filtered has +inf exactly where /rfm/scan_front/labels says REFLECTION or
//      MOTION, the raw range elsewhere, and beams through the known pane come out as REFLECTION,
//      those only (labels in the message's beam order: with the private parameter `clockwise`
//      the scans go clockwise, negative angle_increment, as some drivers send them);
//   3. scans in a frame TF never knows and malformed scans are counted in /rfm/stats and named
//      in /diagnostics;
//   4. ~save_map writes map_server files, only under map_directory (paths out of it, by '..',
//      a symbolic link or an absolute path, are refused by name); ~reset clears the map and
//      ~load_map restores it identically.
// Every wait is a condition with a deadline, never a fixed sleep.
#include "map_copy.h"
#include "reflectance_field_map/LoadMap.h"
#include "reflectance_field_map/RayLabels.h"
#include "reflectance_field_map/RfmStats.h"
#include "reflectance_field_map/SaveMap.h"
#include "tf_messages.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <map_msgs/OccupancyGridUpdate.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

namespace {

using rfm_test::makeTransform;
using rfm_test::MapCopy;
using rfm_test::waitFor;

constexpr double kPi = 3.14159265358979323846;
constexpr double kPaneY = 2.025;  // cell centres at 5 cm: no endpoint on a cell edge
constexpr double kBackWallY = 4.525;
constexpr double kGlassVisibleDeg = 5.0;  // the pane returns the beam within 5 deg of its normal
constexpr double kLaserX = 0.2;           // laser_front in base_link
constexpr int kBeams = 720;               // 0.5 deg over 360 deg
constexpr float kRangeMax = 12.0f;

struct Segment {
  double x0, y0, x1, y1;
  bool glass;
};

// Wall with a window (y = kPaneY), the pane in it, the wall behind the glass, a wall behind
// the robot.
const std::vector<Segment>& scene() {
  static const std::vector<Segment> segments = {
      {-8.0, kPaneY, -1.0, kPaneY, false}, {-1.0, kPaneY, 1.0, kPaneY, true},
      {1.0, kPaneY, 8.0, kPaneY, false},   {-8.0, kBackWallY, 8.0, kBackWallY, false},
      {-8.0, -2.025, 8.0, -2.025, false},
  };
  return segments;
}

// Range along a beam from (ox, oy) in direction `angle`; glass is transparent except near its
// normal. +inf when nothing is hit within range.
float castRay(double ox, double oy, double angle) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  std::vector<std::pair<double, bool>> hits;
  for (const Segment& s : scene()) {
    const double ex = s.x1 - s.x0, ey = s.y1 - s.y0;
    const double denom = dx * ey - dy * ex;
    if (std::fabs(denom) < 1e-12) continue;
    const double t = ((s.x0 - ox) * ey - (s.y0 - oy) * ex) / denom;
    const double u = ((s.x0 - ox) * dy - (s.y0 - oy) * dx) / denom;
    if (t <= 1e-6 || u < 0.0 || u > 1.0) continue;
    bool returns = true;
    if (s.glass) {
      const double length = std::hypot(ex, ey);
      const double cos_incidence = std::fabs(dx * (-ey / length) + dy * (ex / length));
      returns = std::acos(std::min(1.0, cos_incidence)) < kGlassVisibleDeg * kPi / 180.0;
    }
    hits.emplace_back(t, returns);
  }
  std::sort(hits.begin(), hits.end());
  for (const auto& hit : hits) {
    if (hit.second && hit.first < kRangeMax) return static_cast<float>(hit.first);
  }
  return std::numeric_limits<float>::infinity();
}

// Whether the beam at `angle` from (ox, oy) crosses the pane (with a cell's margin at its ends)
// before it ends at `range`.
bool crossesThePane(double ox, double oy, double angle, float range) {
  const double dy = std::sin(angle);
  if (dy <= 1e-9) return false;
  const double t = (kPaneY - oy) / dy;
  const double x = ox + t * std::cos(angle);
  return std::fabs(x) <= 1.05 && t < range;
}

struct ScanRecord {
  double laser_x = 0.0, laser_y = 0.0;
  sensor_msgs::LaserScan raw;
  sensor_msgs::LaserScanPtr filtered;
  reflectance_field_map::RayLabelsPtr labels;
};

class Scenario {
 public:
  Scenario() : spinner_(2) {
    ros::param::param("~clockwise", clockwise_, false);
    scan_pub_ = nh_.advertise<sensor_msgs::LaserScan>("/scan_front", 100);
    rear_pub_ = nh_.advertise<sensor_msgs::LaserScan>("/scan_rear", 100);
    tf_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf", 100);
    tf_static_pub_ = nh_.advertise<tf2_msgs::TFMessage>("/tf_static", 10, true);
    subs_.push_back(nh_.subscribe("/rfm/map", 5, &MapCopy::onMap, &map_));
    subs_.push_back(nh_.subscribe("/rfm/map_updates", 50, &MapCopy::onUpdate, &map_));
    subs_.push_back(nh_.subscribe("/rfm/scan_front/filtered", 500, &Scenario::onFiltered, this));
    subs_.push_back(nh_.subscribe("/rfm/scan_front/labels", 500, &Scenario::onLabels, this));
    subs_.push_back(nh_.subscribe("/rfm/stats", 10, &Scenario::onStats, this));
    subs_.push_back(nh_.subscribe("/rfm/glass_markers", 10, &Scenario::onGlass, this));
    subs_.push_back(nh_.subscribe("/diagnostics", 50, &Scenario::onDiagnostics, this));
    spinner_.start();
  }

  // Subscribed on both sides before anything is published.
  bool connect() {
    return waitFor(
        [&] {
          return scan_pub_.getNumSubscribers() > 0 && rear_pub_.getNumSubscribers() > 0 &&
                 tf_pub_.getNumSubscribers() > 0 && tf_static_pub_.getNumSubscribers() > 0 &&
                 subs_[2].getNumPublishers() > 0 && subs_[3].getNumPublishers() > 0;
        },
        30.0);
  }

  void publishStatic() {
    tf2_msgs::TFMessage msg;
    msg.transforms.push_back(
        makeTransform("base_link", "laser_front", kLaserX, 0.0, 0.0, ros::Time::now(), 0.3));
    tf_static_pub_.publish(msg);
  }

  // One scan from the robot at (x, y), yaw 0, stamped now, with its TF published first.
  void publishScan(double x, double y) {
    const ros::Time stamp = ros::Time::now();
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(makeTransform("odom", "base_link", x, y, 0.0, stamp, 0.3));
    tf_pub_.publish(tf);
    sensor_msgs::LaserScan scan;
    scan.header.stamp = stamp;
    scan.header.frame_id = "laser_front";
    // The same bearings either way: -pi up to pi - step, or from there down to -pi.
    const double step = 2 * kPi / kBeams;
    scan.angle_min = static_cast<float>(clockwise_ ? kPi - step : -kPi);
    scan.angle_increment = static_cast<float>(clockwise_ ? -step : step);
    scan.angle_max = scan.angle_min + (kBeams - 1) * scan.angle_increment;
    scan.range_min = 0.05f;
    scan.range_max = kRangeMax;
    scan.ranges.resize(kBeams);
    for (int i = 0; i < kBeams; ++i) {
      scan.ranges[i] = castRay(x + kLaserX, y, scan.angle_min + i * scan.angle_increment);
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ScanRecord& record = records_[stamp];
      record.laser_x = x + kLaserX;
      record.laser_y = y;
      record.raw = scan;
    }
    scan_pub_.publish(scan);
  }

  // Drives along y = 0 from x0 to x1 at `speed`, one scan every `period` s (paced by the
  // wall clock so TF and scans arrive as they would live).
  void drive(double x0, double x1, double speed, double period) {
    const int steps = static_cast<int>(std::fabs(x1 - x0) / (speed * period));
    ros::WallRate rate(1.0 / period);
    for (int i = 0; i <= steps && ros::ok(); ++i) {
      publishScan(x0 + (x1 - x0) * i / steps, 0.0);
      rate.sleep();
    }
  }

  void onFiltered(const sensor_msgs::LaserScanPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    records_[msg->header.stamp].filtered = msg;
  }
  void onLabels(const reflectance_field_map::RayLabelsPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    records_[msg->header.stamp].labels = msg;
  }
  void onStats(const reflectance_field_map::RfmStatsConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_ = *msg;
    ++stats_count_;
  }
  void onGlass(const visualization_msgs::MarkerArrayConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    glass_markers_ = *msg;
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArrayConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& status : msg->status) {
      std::ostringstream text;
      text << status.name << ": " << status.message;
      for (const auto& kv : status.values)
        text << " | " << kv.key << "=" << kv.value;
      diagnostics_[status.name] = text.str();
    }
  }

  size_t completeRecords() {
    std::lock_guard<std::mutex> lock(mutex_);
    size_t n = 0;
    for (const auto& r : records_)
      n += r.second.filtered && r.second.labels ? 1 : 0;
    return n;
  }

  ros::NodeHandle nh_;
  bool clockwise_ = false;
  ros::AsyncSpinner spinner_;
  ros::Publisher scan_pub_, rear_pub_, tf_pub_, tf_static_pub_;
  std::vector<ros::Subscriber> subs_;
  MapCopy map_;
  std::mutex mutex_;
  std::map<ros::Time, ScanRecord> records_;
  reflectance_field_map::RfmStats stats_;
  int stats_count_ = 0;
  visualization_msgs::MarkerArray glass_markers_;
  std::map<std::string, std::string> diagnostics_;
};

Scenario* scenario = nullptr;
bool driven = false;
size_t scans_in_drive = 0;

// Drives once; every test starts from the mapped scene.
void ensureDriven() {
  if (driven) return;
  driven = true;
  ASSERT_TRUE(scenario->connect()) << "rfm node did not connect";
  scenario->publishStatic();
  scenario->drive(-5.0, 5.0, 1.0, 0.025);  // 10 m at 1 m/s, 40 scans/s
  // Then stand still at x = 2.5 (beams cross the pane at 20-40 deg from its normal).
  for (int i = 0; i < 40; ++i) {
    scenario->publishScan(2.5, 0.0);
    ros::WallDuration(0.025).sleep();  // pacing the publisher, as a live laser would
  }
  std::lock_guard<std::mutex> lock(scenario->mutex_);
  scans_in_drive = scenario->records_.size();
}

TEST(SyntheticScene, MapHasThePaneAndTheWallOccupied) {
  ensureDriven();
  MapCopy& map = scenario->map_;
  auto pane_and_wall = [&] {
    for (double x : {-0.6, -0.3, 0.0, 0.3, 0.6}) {
      if (!map.occupiedNear(x, kPaneY)) return false;
    }
    return map.occupiedNear(-3.0, kPaneY) && map.occupiedNear(3.0, kPaneY);
  };
  EXPECT_TRUE(waitFor(pane_and_wall, 30.0))
      << "full maps " << map.full_maps << ", updates " << map.updates << ", occupied cells "
      << map.countOccupied() << ", pane centre " << map.at(0.0, kPaneY) << ", wall "
      << map.at(-3.0, kPaneY);
  // Free space between the robot and the pane.
  EXPECT_EQ(map.at(0.0, 1.0), 0);
  EXPECT_GT(map.updates + map.full_maps, 1);
  // The pane shows up as glass markers (blue cubes).
  EXPECT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(scenario->mutex_);
        for (const auto& m : scenario->glass_markers_.markers) {
          if (m.ns == "glass" && !m.points.empty()) return true;
        }
        return false;
      },
      10.0))
      << "no glass markers; markers by namespace: " << [&] {
           std::lock_guard<std::mutex> lock(scenario->mutex_);
           std::string seen;
           for (const auto& m : scenario->glass_markers_.markers) {
             seen += m.ns + "=" + std::to_string(m.points.size()) + " ";
           }
           return seen;
         }();
}

// /rfm/stats says how far /rfm/map_updates trails the motion-removal passes: the drive's passes
// change the map, so they are timed from their start to their update.
TEST(SyntheticScene, StatsTimeEachPassToItsMapUpdate) {
  ensureDriven();
  auto timed = [&] {
    std::lock_guard<std::mutex> lock(scenario->mutex_);
    return scenario->stats_.pass_to_update_ms_max > 0.0;
  };
  EXPECT_TRUE(waitFor(timed, 10.0)) << "no pass timed in /rfm/stats";
  std::lock_guard<std::mutex> lock(scenario->mutex_);
  const reflectance_field_map::RfmStats& stats = scenario->stats_;
  EXPECT_GT(stats.pass_to_update_ms_median, 0.0);
  EXPECT_LE(stats.pass_to_update_ms_median, stats.pass_to_update_ms_p99);
  // Quantiles are their bucket's upper edge, 2 % wide.
  EXPECT_LE(stats.pass_to_update_ms_p99, stats.pass_to_update_ms_max * 1.03);
}

// Rays through the pane (seen away from its normal) reach the back wall: the cells they cross
// between the pane and the back wall are free space, never obstacles.
TEST(SyntheticScene, NoPhantomObstaclesBehindTheGlass) {
  ensureDriven();
  MapCopy& map = scenario->map_;
  ASSERT_TRUE(waitFor([&] { return map.occupiedNear(0.0, kPaneY); }, 30.0));
  int phantom = 0, checked = 0;
  for (double x = -0.8; x <= 0.8; x += 0.1) {
    for (double y = kPaneY + 0.3; y < kBackWallY - 0.3; y += 0.1) {
      const int value = map.at(x, y);
      if (value == -2) continue;
      ++checked;
      if (value == 100) ++phantom;
    }
  }
  EXPECT_GT(checked, 0);
  EXPECT_EQ(phantom, 0) << phantom << " of " << checked
                        << " sampled cells between the pane and the back wall are occupied";
}

TEST(SyntheticScene, FilteredScansDropReflectionsAndMotion) {
  ensureDriven();
  // Every scan processed comes back filtered and labelled.
  EXPECT_TRUE(waitFor([&] { return scenario->completeRecords() >= scans_in_drive * 9 / 10; }, 20.0))
      << scenario->completeRecords() << " of " << scans_in_drive << " scans came back";
  std::lock_guard<std::mutex> lock(scenario->mutex_);
  size_t reflections = 0, reflections_in_last = 0, kept = 0, checked = 0, off_the_pane = 0;
  size_t index = 0;
  for (const auto& entry : scenario->records_) {
    ++index;
    const ScanRecord& r = entry.second;
    if (!r.filtered || !r.labels) continue;
    ASSERT_EQ(r.labels->labels.size(), r.raw.ranges.size());
    ASSERT_EQ(r.filtered->ranges.size(), r.raw.ranges.size());
    ++checked;
    for (size_t i = 0; i < r.raw.ranges.size(); ++i) {
      const uint8_t label = r.labels->labels[i];
      const float out = r.filtered->ranges[i];
      if (label == reflectance_field_map::RayLabels::REFLECTION ||
          label == reflectance_field_map::RayLabels::MOTION) {
        EXPECT_TRUE(std::isinf(out) && out > 0) << "beam " << i << " labelled " << int(label);
        if (label == reflectance_field_map::RayLabels::REFLECTION) {
          ++reflections;
          const double angle = r.raw.angle_min + static_cast<double>(i) * r.raw.angle_increment;
          if (!crossesThePane(r.laser_x, r.laser_y, angle, r.raw.ranges[i])) ++off_the_pane;
          if (index + 20 > scenario->records_.size()) ++reflections_in_last;
        }
      } else {
        const float in = r.raw.ranges[i];
        EXPECT_TRUE(in == out || (std::isinf(in) && std::isinf(out))) << "beam " << i;
        if (label == reflectance_field_map::RayLabels::KEPT) ++kept;
      }
    }
  }
  EXPECT_GT(checked, 0u);
  EXPECT_GT(kept, 0u);
  // Standing at x = 2.5 after the pane is mapped, the beams through it see the back wall:
  // reflections (transmitted rays), removed from the filtered scan.
  EXPECT_GT(reflections_in_last, 0u) << reflections << " reflection labels in all";
  // Only glass cuts rays here: a REFLECTION on a beam that misses the pane is a label on the
  // wrong beam (or a phantom cut).
  EXPECT_EQ(off_the_pane, 0u) << "of " << reflections << " reflection labels";
  std::cout << "[ INFO     ] " << checked << " scans checked, " << kept << " beams kept, "
            << reflections << " reflections (" << reflections_in_last << " in the last 20 scans)"
            << std::endl;
}

TEST(SyntheticScene, ScansWithoutTransformAndMalformedScansAreCounted) {
  ensureDriven();
  uint64_t dropped_before = 0;
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(scenario->mutex_);
        dropped_before = scenario->stats_.scans_dropped;
        return scenario->stats_count_ > 0;
      },
      10.0));
  // 30 scans on /scan_rear in a frame TF never heard of (queue of 20: at least 10 overflow),
  // then 5 malformed ones (range count does not match the angles).
  for (int i = 0; i < 30; ++i) {
    sensor_msgs::LaserScan scan;
    scan.header.stamp = ros::Time::now();
    scan.header.frame_id = "laser_nowhere";
    scan.angle_min = -1.0f;
    scan.angle_increment = 0.01f;
    scan.angle_max = scan.angle_min + 99 * scan.angle_increment;
    scan.range_min = 0.1f;
    scan.range_max = 10.0f;
    scan.ranges.assign(100, 3.0f);
    if (i >= 25) scan.ranges.resize(40);  // malformed
    scenario->rear_pub_.publish(scan);
    ros::WallDuration(0.01).sleep();  // pacing
  }
  EXPECT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(scenario->mutex_);
        return scenario->stats_.scans_dropped >= dropped_before + 10;
      },
      15.0))
      << "scans_dropped " << scenario->stats_.scans_dropped;
  EXPECT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(scenario->mutex_);
        for (const auto& d : scenario->diagnostics_) {
          if (d.second.find("laser_nowhere") != std::string::npos) return true;
        }
        return false;
      },
      15.0))
      << "no diagnostic names the missing frame";
  EXPECT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(scenario->mutex_);
        for (const auto& d : scenario->diagnostics_) {
          if (d.first.find("Scan input") != std::string::npos &&
              d.second.find("5 malformed") != std::string::npos) {
            return true;
          }
        }
        return false;
      },
      15.0))
      << "malformed scans not reported";
}

// P5 PGM -> occupancy in OccupancyGrid row order (bottom row first).
bool readPgm(const std::string& path, std::vector<int8_t>& data, int& width, int& height) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  in >> magic;
  if (magic != "P5") return false;
  auto skip = [&] {
    in >> std::ws;
    while (in.peek() == '#') {
      std::string line;
      std::getline(in, line);
      in >> std::ws;
    }
  };
  int maxval = 0;
  skip();
  in >> width;
  skip();
  in >> height;
  skip();
  in >> maxval;
  in.get();
  std::vector<unsigned char> pixels(static_cast<size_t>(width) * height);
  in.read(reinterpret_cast<char*>(pixels.data()), static_cast<std::streamsize>(pixels.size()));
  if (!in || maxval != 255) return false;
  data.resize(pixels.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const unsigned char p = pixels[static_cast<size_t>(height - 1 - y) * width + x];
      data[static_cast<size_t>(y) * width + x] = p == 0 ? 100 : p == 254 ? 0 : p == 205 ? -1 : 50;
    }
  }
  return true;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

TEST(SyntheticScene, SaveResetLoadRoundTrip) {
  ensureDriven();
  ASSERT_TRUE(waitFor([&] { return scenario->map_.countOccupied() > 0; }, 30.0));
  ros::NodeHandle nh;
  const std::string node = "/rfm";
  ros::ServiceClient save = nh.serviceClient<reflectance_field_map::SaveMap>(node + "/save_map");
  ros::ServiceClient load = nh.serviceClient<reflectance_field_map::LoadMap>(node + "/load_map");
  ros::ServiceClient reset = nh.serviceClient<std_srvs::Trigger>(node + "/reset");
  ASSERT_TRUE(save.waitForExistence(ros::Duration(10.0)));
  ASSERT_TRUE(load.waitForExistence(ros::Duration(10.0)));
  ASSERT_TRUE(reset.waitForExistence(ros::Duration(10.0)));

  // The node saves and loads only under its map_directory (a fresh one per launch).
  std::string dir;
  ASSERT_TRUE(nh.getParam(node + "/map_directory", dir));
  std::filesystem::create_directories(dir);

  // Paths out of it are refused with a message naming them: absolute, climbing with '..', or
  // through a symbolic link that leads out.
  const std::string outside = dir + "_outside";
  std::filesystem::create_directories(outside);
  std::filesystem::remove(dir + "/escape");
  std::filesystem::create_directory_symlink(outside, dir + "/escape");
  for (const std::string& path :
       {std::string("/nonexistent_rfm_dir/sub/map"), std::string("maps/../../etc/x"),
        std::string("escape/map"), outside + "/map"}) {
    reflectance_field_map::SaveMap bad;
    bad.request.path = path;
    ASSERT_TRUE(save.call(bad));
    EXPECT_FALSE(bad.response.success) << path;
    EXPECT_NE(bad.response.message.find(path), std::string::npos) << bad.response.message;
    reflectance_field_map::LoadMap bad_load;
    bad_load.request.path = path;
    ASSERT_TRUE(load.call(bad_load));
    EXPECT_FALSE(bad_load.response.success) << path;
  }
  EXPECT_TRUE(std::filesystem::is_empty(outside));
  EXPECT_FALSE(std::filesystem::exists("/nonexistent_rfm_dir"));

  // Missing directories under it are created; an absolute path inside it is fine.
  reflectance_field_map::SaveMap nested;
  nested.request.path = dir + "/runs/today/map";
  ASSERT_TRUE(save.call(nested));
  EXPECT_TRUE(nested.response.success) << nested.response.message;
  EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/runs/today/map.rfm"));

  reflectance_field_map::SaveMap first;
  first.request.path = "first";
  ASSERT_TRUE(save.call(first));
  ASSERT_TRUE(first.response.success) << first.response.message;
  std::vector<int8_t> saved;
  int width = 0, height = 0;
  ASSERT_TRUE(readPgm(dir + "/first.pgm", saved, width, height));
  EXPECT_GT(std::count(saved.begin(), saved.end(), 100), 0);
  const std::string yaml = readFile(dir + "/first.yaml");
  EXPECT_NE(yaml.find("image: first.pgm"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("resolution: 0.05"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("negate: 0"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("occupied_thresh: 0.65"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("free_thresh: 0.196"), std::string::npos) << yaml;
  EXPECT_FALSE(readFile(dir + "/first.rfm").empty());

  // The published map matches the file once the save's own motion-removal pass arrived.
  auto matches = [&](const std::vector<int8_t>& expected) {
    const nav_msgs::OccupancyGrid grid = scenario->map_.copy();
    return static_cast<int>(grid.info.width) == width &&
           static_cast<int>(grid.info.height) == height && grid.data == expected;
  };
  EXPECT_TRUE(waitFor([&] { return matches(saved); }, 10.0)) << "/rfm/map differs from first.pgm";

  std_srvs::Trigger clear;
  const int maps_before_reset = scenario->map_.full_maps;
  ASSERT_TRUE(reset.call(clear));
  EXPECT_TRUE(clear.response.success);
  EXPECT_TRUE(waitFor(
      [&] {
        return scenario->map_.full_maps > maps_before_reset && scenario->map_.countOccupied() == 0;
      },
      10.0))
      << "map not cleared by ~reset";

  reflectance_field_map::LoadMap resume;
  resume.request.path = "first";
  const int maps_before_load = scenario->map_.full_maps;
  ASSERT_TRUE(load.call(resume));
  ASSERT_TRUE(resume.response.success) << resume.response.message;
  EXPECT_TRUE(
      waitFor([&] { return scenario->map_.full_maps > maps_before_load && matches(saved); }, 10.0))
      << "map after ~load_map differs from the saved one";

  reflectance_field_map::SaveMap second;
  second.request.path = "second";
  ASSERT_TRUE(save.call(second));
  ASSERT_TRUE(second.response.success) << second.response.message;
  EXPECT_EQ(readFile(dir + "/first.pgm"), readFile(dir + "/second.pgm"));

  reflectance_field_map::LoadMap missing;
  missing.request.path = "does_not_exist";
  ASSERT_TRUE(load.call(missing));
  EXPECT_FALSE(missing.response.success);
  EXPECT_FALSE(missing.response.message.empty());

  std::filesystem::remove_all(dir);
  std::filesystem::remove_all(outside);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "rfm_synthetic_scene_test");
  Scenario s;
  scenario = &s;
  const int result = RUN_ALL_TESTS();
  scenario = nullptr;
  return result;
}
