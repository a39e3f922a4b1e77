// rfm_offline end to end: bags written here with rosbag (two lidars + TF, a stationary lidar
// without TF), the real stationary recording of shared/data, and the error paths.

#include "../scratch_directory_test.h"
#include "reflectance_field_map/RayLabels.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/render/png_io.h"

#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>
#include <yaml-cpp/yaml.h>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>

namespace {

namespace fs = std::filesystem;

constexpr int kBeams = 181;
constexpr int kScansPerTopic = 20;
constexpr uint32_t kHugeBeams = (1u << 21) + 2048;  // more bytes than any scan rfm_offline takes
const double kStart = 1000.0;

struct RunResult {
  int code = -1;
  std::string output;
};

RunResult runOffline(const std::string& arguments) {
  const std::string command = std::string(RFM_OFFLINE_EXE) + " " + arguments + " 2>&1";
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

// Range from `origin` along `angle` to the walls of the square room [-3, 3]^2.
float roomRange(double ox, double oy, double angle) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  double t = std::numeric_limits<double>::infinity();
  if (dx > 1e-9) t = std::min(t, (3.0 - ox) / dx);
  if (dx < -1e-9) t = std::min(t, (-3.0 - ox) / dx);
  if (dy > 1e-9) t = std::min(t, (3.0 - oy) / dy);
  if (dy < -1e-9) t = std::min(t, (-3.0 - oy) / dy);
  return static_cast<float>(t);
}

geometry_msgs::TransformStamped transform(const std::string& parent, const std::string& child,
                                          double t, double x, double y, double yaw) {
  geometry_msgs::TransformStamped tf;
  tf.header.stamp = ros::Time(t);
  tf.header.frame_id = parent;
  tf.child_frame_id = child;
  tf.transform.translation.x = x;
  tf.transform.translation.y = y;
  tf.transform.rotation.z = std::sin(yaw / 2);
  tf.transform.rotation.w = std::cos(yaw / 2);
  return tf;
}

double robotX(double t) {
  return -0.5 + 0.5 * (t - kStart);
}

// What a test bag holds besides the plain drive.
struct BagShape {
  bool with_tf = true;
  double tf_from = kStart - 0.2;          // the first odom transform
  double jump_from = 0.0, jump_to = 0.0;  // odom puts the robot 370 m away in [from, to)
  // Changes scan i (0..kScansPerTopic-1) of the rear or front lidar before it is written.
  std::function<void(int i, bool rear, sensor_msgs::LaserScan& scan)> edit;
};

// Two lidars on a robot driving along x in a square room. The rear lidar looks backwards and
// reports its beams clockwise (negative angle_increment). Beam 0 of every scan is NaN.
void writeRobotBag(const std::string& path, const BagShape& shape) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  if (shape.with_tf) {
    tf2_msgs::TFMessage statics;
    statics.transforms.push_back(transform("base_link", "laser_front", kStart, 0.2, 0.0, 0.0));
    statics.transforms.push_back(transform("base_link", "laser_rear", kStart, -0.2, 0.0, M_PI));
    bag.write("/tf_static", ros::Time(kStart - 0.3), statics);
    for (double t = shape.tf_from; t < kStart + 2.25; t += 0.02) {
      const bool jumped = t >= shape.jump_from && t < shape.jump_to;
      tf2_msgs::TFMessage odom;
      odom.transforms.push_back(
          transform("odom", "base_link", t, robotX(t) + (jumped ? 370.0 : 0.0), 0.0, 0.0));
      bag.write("/tf", ros::Time(t), odom);
    }
  }
  uint32_t seq = 0;
  for (int i = 0; i < kScansPerTopic; ++i) {
    for (int rear = 0; rear < 2; ++rear) {
      const double t = kStart + 0.1 * i + 0.05 * rear;
      sensor_msgs::LaserScan scan;
      scan.header.seq = seq++;
      scan.header.stamp = ros::Time(t);
      scan.header.frame_id = rear ? "laser_rear" : "laser_front";
      scan.angle_increment = static_cast<float>(rear ? -M_PI / 180 : M_PI / 180);
      scan.angle_min = static_cast<float>(rear ? M_PI / 2 : -M_PI / 2);
      scan.angle_max = static_cast<float>(rear ? -M_PI / 2 : M_PI / 2);
      scan.range_min = 0.05f;
      scan.range_max = 10.0f;
      const double lx = robotX(t) + (rear ? -0.2 : 0.2);
      const double heading = rear ? M_PI : 0.0;
      for (int b = 0; b < kBeams; ++b) {
        const double angle = heading + scan.angle_min + b * scan.angle_increment;
        scan.ranges.push_back(b == 0 ? std::numeric_limits<float>::quiet_NaN()
                                     : roomRange(lx, 0.0, angle));
      }
      if (shape.edit) shape.edit(i, rear, scan);
      bag.write(rear ? "/scan_rear" : "/scan_front", ros::Time(t + 0.001), scan);
    }
  }
  bag.close();
}

// With `short_scan` >= 0, that scan of each lidar lost the second half of its ranges.
void writeRobotBag(const std::string& path, bool with_tf, int short_scan = -1) {
  BagShape shape;
  shape.with_tf = with_tf;
  if (short_scan >= 0) {
    shape.edit = [short_scan](int i, bool, sensor_msgs::LaserScan& scan) {
      if (i == short_scan) scan.ranges.resize(kBeams / 2);
    };
  }
  writeRobotBag(path, shape);
}

class OfflineEndToEnd : public rfm_test::ScratchDirectoryTest {};

void expectOutputs(const std::string& out) {
  for (const char* name :
       {"map.yaml", "map.pgm", "classes.pgm", "layers.png", "labels.bag", "summary.json"}) {
    EXPECT_TRUE(fs::is_regular_file(fs::path(out) / name)) << name;
    EXPECT_GT(fs::file_size(fs::path(out) / name), 0u) << name;
  }
}

TEST_F(OfflineEndToEnd, TwoLidarsWithTf) {
  writeRobotBag(path("in.bag"), true);
  const std::string out = path("out");
  const RunResult run = runOffline("--bag " + path("in.bag") + " --out " + out);
  ASSERT_EQ(run.code, 0) << run.output;
  expectOutputs(out);

  // map_server files.
  const YAML::Node map_yaml = YAML::LoadFile(out + "/map.yaml");
  EXPECT_EQ(map_yaml["image"].as<std::string>(), "map.pgm");
  EXPECT_DOUBLE_EQ(map_yaml["resolution"].as<double>(), 0.05);
  ASSERT_EQ(map_yaml["origin"].size(), 3u);
  EXPECT_EQ(map_yaml["negate"].as<int>(), 0);
  EXPECT_DOUBLE_EQ(map_yaml["occupied_thresh"].as<double>(), 0.65);
  EXPECT_DOUBLE_EQ(map_yaml["free_thresh"].as<double>(), 0.196);
  std::ifstream pgm(out + "/map.pgm", std::ios::binary);
  std::string magic, comment;
  pgm >> magic;
  EXPECT_EQ(magic, "P5");
  pgm.ignore(1);
  std::getline(pgm, comment);
  int width = 0, height = 0, max_value = 0;
  pgm >> width >> height >> max_value;
  pgm.ignore(1);
  EXPECT_EQ(max_value, 255);
  EXPECT_GT(width, 100);  // the 6 m room at 5 cm
  EXPECT_GT(height, 100);
  std::vector<unsigned char> pixels(static_cast<size_t>(width) * static_cast<size_t>(height));
  pgm.read(reinterpret_cast<char*>(pixels.data()), static_cast<std::streamsize>(pixels.size()));
  ASSERT_TRUE(pgm.good());
  std::map<int, int> values;
  for (unsigned char p : pixels)
    ++values[p];
  for (const auto& [value, count] : values) {
    EXPECT_TRUE(value == 0 || value == 205 || value == 254) << value << " x " << count;
  }
  EXPECT_GT(values[254], 0);  // the room is free

  // classes.pgm: map.pgm's cells, a class code each, agreeing with map.pgm cell by cell.
  std::ifstream classes_pgm(out + "/classes.pgm", std::ios::binary);
  int classes_width = 0, classes_height = 0;
  classes_pgm >> magic;
  EXPECT_EQ(magic, "P5");
  classes_pgm.ignore(1);
  std::getline(classes_pgm, comment);
  classes_pgm >> classes_width >> classes_height >> max_value;
  classes_pgm.ignore(1);
  ASSERT_EQ(classes_width, width);
  ASSERT_EQ(classes_height, height);
  EXPECT_EQ(max_value, 255);
  std::vector<unsigned char> codes(pixels.size());
  classes_pgm.read(reinterpret_cast<char*>(codes.data()),
                   static_cast<std::streamsize>(codes.size()));
  ASSERT_TRUE(classes_pgm.good());
  std::map<int, int> code_counts;
  for (size_t i = 0; i < codes.size(); ++i) {
    ++code_counts[codes[i]];
    const int expected_pgm = codes[i] == 0 ? 205 : (codes[i] >= 2 && codes[i] <= 4 ? 0 : 254);
    ASSERT_LE(codes[i], 5) << "cell " << i;
    ASSERT_EQ(pixels[i], expected_pgm) << "cell " << i << " code " << int(codes[i]);
  }
  EXPECT_GT(code_counts[1], 0);                   // free
  EXPECT_GT(code_counts[2] + code_counts[3], 0);  // the room's walls

  const rfm::render::RgbImage layers = rfm::render::readPng(out + "/layers.png");
  EXPECT_EQ(layers.width() % width, 0);
  EXPECT_EQ(layers.width() / width, layers.height() / height);

  // One RayLabels per scan, header copied, a label per beam in the bag's beam order.
  rosbag::Bag labels_bag(out + "/labels.bag");
  rosbag::View view(labels_bag);
  std::map<uint32_t, int> per_seq;
  int messages = 0;
  for (const rosbag::MessageInstance& m : view) {
    EXPECT_EQ(m.getTopic(), "/rfm/ray_labels");
    const auto labels = m.instantiate<reflectance_field_map::RayLabels>();
    ASSERT_TRUE(labels);
    ++messages;
    ++per_seq[labels->header.seq];
    const uint32_t seq = labels->header.seq;
    const bool rear = seq % 2 == 1;
    EXPECT_EQ(labels->scan_topic, rear ? "/scan_rear" : "/scan_front");
    EXPECT_EQ(labels->header.frame_id, rear ? "laser_rear" : "laser_front");
    EXPECT_NEAR(labels->header.stamp.toSec(), kStart + 0.1 * (seq / 2) + 0.05 * rear, 1e-6);
    ASSERT_EQ(labels->labels.size(), static_cast<size_t>(kBeams));
    EXPECT_EQ(labels->labels[0], reflectance_field_map::RayLabels::NO_RETURN);  // the NaN beam
    for (size_t b = 1; b < labels->labels.size(); ++b) {
      EXPECT_LE(labels->labels[b], reflectance_field_map::RayLabels::REFLECTION);
    }
  }
  EXPECT_EQ(messages, 2 * kScansPerTopic);
  EXPECT_EQ(per_seq.size(), static_cast<size_t>(2 * kScansPerTopic));

  // summary.json (JSON is YAML).
  const YAML::Node summary = YAML::LoadFile(out + "/summary.json");
  EXPECT_EQ(summary["mode"].as<std::string>(), "full");
  EXPECT_EQ(summary["scans"]["total"].as<int>(), 2 * kScansPerTopic);
  EXPECT_EQ(summary["scans"]["per_topic"]["/scan_front"].as<int>(), kScansPerTopic);
  EXPECT_EQ(summary["rays"].as<int>(), 2 * kScansPerTopic * kBeams);
  int labelled = 0;
  for (const char* name : {"no_return", "kept", "motion", "reflection"}) {
    labelled += summary["labels"][name].as<int>();
  }
  EXPECT_EQ(labelled, 2 * kScansPerTopic * kBeams);
  EXPECT_GE(summary["labels"]["no_return"].as<int>(), 2 * kScansPerTopic);
  EXPECT_GT(summary["timing"]["real_time_factor"].as<double>(), 0.0);
  EXPECT_GT(summary["timing"]["wall_s"].as<double>(), 0.0);
  EXPECT_NEAR(summary["timing"]["recording_s"].as<double>(), 1.95, 1e-6);
  for (const char* stage : {"read_bag", "process", "write_labels"}) {
    EXPECT_TRUE(summary["timing"]["stages_s"][stage]) << stage;
  }
  EXPECT_EQ(summary["map"]["width"].as<int>(), width);
  for (const rfm::OptionField& field : rfm::optionFields()) {
    EXPECT_TRUE(summary["parameters"][field.name]) << field.name;
  }
}

TEST_F(OfflineEndToEnd, ModesAndThetaView) {
  writeRobotBag(path("in.bag"), true);
  const std::string params = path("params.yaml");
  std::ofstream(params) << "rfm:\n  resolution: 0.1\n  theta_bins: 90\n";
  struct Case {
    std::string flags;
    std::string mode;
  };
  for (const Case& c : {Case{"--baseline", "plain_grid"},
                        Case{"--no-motion-removal --no-reflection-removal", "basic_rfm"},
                        Case{"--no-reflection-removal", "motion_removal"},
                        Case{"--no-motion-removal", "reflection_removal"}}) {
    const std::string out = path("out_" + c.mode);
    const RunResult run = runOffline("--bag " + path("in.bag") + " --out " + out + " --params " +
                                     params + " " + c.flags + " --theta-view=-2.9,1.0,-2.9,-1.0");
    ASSERT_EQ(run.code, 0) << c.flags << "\n" << run.output;
    expectOutputs(out);
    const YAML::Node summary = YAML::LoadFile(out + "/summary.json");
    EXPECT_EQ(summary["mode"].as<std::string>(), c.mode);
    EXPECT_DOUBLE_EQ(summary["parameters"]["resolution"].as<double>(), 0.1);
    EXPECT_EQ(summary["parameters"]["theta_bins"].as<int>(), 90);
    if (c.mode == "plain_grid") {  // no field to look at
      EXPECT_FALSE(fs::exists(out + "/theta_view.png"));
      EXPECT_NE(run.output.find("no reflectance field"), std::string::npos) << run.output;
      continue;
    }
    const rfm::render::RgbImage theta = rfm::render::readPng(out + "/theta_view.png");
    EXPECT_GT(theta.width(), 0);
    EXPECT_EQ(theta.height() % 90, 0);  // one row (or a few pixels) per bin
  }
}

TEST_F(OfflineEndToEnd, StationaryLidarWithoutTf) {
  writeRobotBag(path("in.bag"), false);
  // Default fixed frame: the bag has no TF, the message says what to pass.
  RunResult run = runOffline("--bag " + path("in.bag") + " --out " + path("out1"));
  EXPECT_EQ(run.code, 1) << run.output;
  EXPECT_NE(run.output.find("no /tf"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("--fixed-frame laser_"), std::string::npos) << run.output;

  run = runOffline("--bag " + path("in.bag") + " --out " + path("out2") +
                   " --scan-topics /scan_front,/absent --fixed-frame laser_front");
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("/absent is not in the bag"), std::string::npos) << run.output;
  expectOutputs(path("out2"));
  const YAML::Node summary = YAML::LoadFile(path("out2/summary.json"));
  ASSERT_EQ(summary["scans"]["missing_topics"].size(), 1u);
  EXPECT_EQ(summary["scans"]["missing_topics"][0].as<std::string>(), "/absent");
  rosbag::Bag labels_bag(path("out2/labels.bag"));
  EXPECT_EQ(rosbag::View(labels_bag).size(), static_cast<uint32_t>(kScansPerTopic));
}

// A lidar spinning in place at 3 rad/s at the middle of the square room, sweeping each 10 Hz
// scan beam by beam (time_increment): the sensor turns 0.3 rad during a sweep. Written with the
// message's time_increment or with 0 (the same ranges, the sweep unsaid).
void writeSpinningBag(const std::string& path, bool say_time_increment) {
  constexpr double kTurnRate = 3.0, kScanPeriod = 0.1;
  constexpr int kSpinBeams = 720;
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage statics;
  statics.transforms.push_back(transform("base_link", "laser", kStart, 0.0, 0.0, 0.0));
  bag.write("/tf_static", ros::Time(kStart - 0.3), statics);
  for (double t = kStart - 0.2; t < kStart + 2.3; t += 0.01) {
    tf2_msgs::TFMessage odom;
    odom.transforms.push_back(
        transform("odom", "base_link", t, 0.0, 0.0, kTurnRate * (t - kStart)));
    bag.write("/tf", ros::Time(t), odom);
  }
  const double time_increment = kScanPeriod / kSpinBeams;
  for (int i = 0; i < 20; ++i) {
    const double t = kStart + kScanPeriod * i;
    sensor_msgs::LaserScan scan;
    scan.header.seq = i;
    scan.header.stamp = ros::Time(t);
    scan.header.frame_id = "laser";
    scan.angle_increment = static_cast<float>(2.0 * M_PI / kSpinBeams);
    scan.angle_min = static_cast<float>(-M_PI);
    scan.angle_max = scan.angle_min + scan.angle_increment * (kSpinBeams - 1);
    scan.time_increment = say_time_increment ? static_cast<float>(time_increment) : 0.0f;
    scan.scan_time = static_cast<float>(kScanPeriod);
    scan.range_min = 0.05f;
    scan.range_max = 10.0f;
    for (int b = 0; b < kSpinBeams; ++b) {
      const double yaw = kTurnRate * (t + b * time_increment - kStart);
      scan.ranges.push_back(roomRange(0.0, 0.0, yaw + scan.angle_min + b * scan.angle_increment));
    }
    bag.write("/scan", ros::Time(t + kScanPeriod), scan);
  }
  bag.close();
}

// Occupied cells of DIR/map.pgm farther than `tolerance` (m) from the room's walls, and all.
std::pair<int, int> cellsOffTheWalls(const std::string& dir, double tolerance) {
  const YAML::Node map_yaml = YAML::LoadFile(dir + "/map.yaml");
  const double resolution = map_yaml["resolution"].as<double>();
  const double origin_x = map_yaml["origin"][0].as<double>();
  const double origin_y = map_yaml["origin"][1].as<double>();
  std::ifstream pgm(dir + "/map.pgm", std::ios::binary);
  std::string magic, comment;
  int width = 0, height = 0, max_value = 0;
  pgm >> magic;
  pgm.ignore(1);
  std::getline(pgm, comment);
  pgm >> width >> height >> max_value;
  pgm.ignore(1);
  std::vector<unsigned char> pixels(static_cast<size_t>(width) * static_cast<size_t>(height));
  pgm.read(reinterpret_cast<char*>(pixels.data()), static_cast<std::streamsize>(pixels.size()));
  EXPECT_TRUE(pgm.good());
  int off = 0, occupied = 0;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      if (pixels[static_cast<size_t>(row) * width + col] != 0) continue;
      const double x = origin_x + (col + 0.5) * resolution;
      const double y = origin_y + (height - 1 - row + 0.5) * resolution;
      ++occupied;
      off += std::abs(3.0 - std::max(std::abs(x), std::abs(y))) > tolerance;
    }
  }
  return {off, occupied};
}

TEST_F(OfflineEndToEnd, ASweepingLidarThatTurnsDrawsStraightWalls) {
  writeSpinningBag(path("said.bag"), true);
  writeSpinningBag(path("unsaid.bag"), false);
  const RunResult said =
      runOffline("--bag " + path("said.bag") + " --out " + path("said") + " --scan-topics /scan");
  ASSERT_EQ(said.code, 0) << said.output;
  EXPECT_NE(said.output.find("scans turned as the sensor turned"), std::string::npos)
      << said.output;
  const RunResult unsaid = runOffline("--bag " + path("unsaid.bag") + " --out " + path("unsaid") +
                                      " --scan-topics /scan");
  ASSERT_EQ(unsaid.code, 0) << unsaid.output;
  // Each beam placed where the sensor pointed when it measured it: the walls stay walls.
  const auto [said_off, said_occupied] = cellsOffTheWalls(path("said"), 0.1);
  EXPECT_GT(said_occupied, 300) << "the room's 24 m of wall at 5 cm";
  EXPECT_EQ(said_off, 0) << "of " << said_occupied;
  // Stamped at the first beam's pose, the scan smears the walls by up to 0.9 m.
  const auto [unsaid_off, unsaid_occupied] = cellsOffTheWalls(path("unsaid"), 0.1);
  EXPECT_GT(unsaid_off, unsaid_occupied / 4);
}

TEST_F(OfflineEndToEnd, MissingTransformsAreCounted) {
  writeRobotBag(path("in.bag"), true);
  const RunResult run =
      runOffline("--bag " + path("in.bag") + " --out " + path("out") + " --base-frame nowhere");
  EXPECT_EQ(run.code, 1) << run.output;
  EXPECT_NE(run.output.find("40 of 40 scans"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("/scan_front: 20 of 20"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("--base-frame"), std::string::npos) << run.output;
}

uint64_t labelMessages(const std::string& labels_bag) {
  rosbag::Bag bag(labels_bag);
  return rosbag::View(bag).size();
}

// A scan with fewer ranges than its angles say would put every beam at a wrong bearing: it is
// skipped and counted, the others are mapped. The bag is read in two halves side by side: short
// scans early (t = 1000.3) and late (t = 1001.5) are both found and counted once.
TEST_F(OfflineEndToEnd, ScansWithTooFewRangesAreSkippedAndCounted) {
  for (const int short_scan : {3, 15}) {
    SCOPED_TRACE("short scan " + std::to_string(short_scan));
    writeRobotBag(path("in.bag"), true, short_scan);
    const RunResult run = runOffline("--bag " + path("in.bag") + " --out " + path("out"));
    ASSERT_EQ(run.code, 0) << run.output;
    EXPECT_NE(run.output.find("warning: skipped 2 of 40 scans are malformed (malformed): "
                              "/scan_front: 1 of 20; /scan_rear: 1 of 20;"),
              std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("90 ranges"), std::string::npos) << run.output;
    EXPECT_EQ(labelMessages(path("out/labels.bag")), 38u);
    const YAML::Node summary = YAML::LoadFile(path("out/summary.json"));
    EXPECT_EQ(summary["scans"]["total"].as<int>(), 38);
    EXPECT_EQ(summary["scans"]["read"].as<int>(), 40);
    EXPECT_EQ(summary["scans"]["skipped"]["total"].as<int>(), 2);
    EXPECT_EQ(summary["scans"]["skipped"]["per_topic"]["/scan_rear"]["malformed"].as<int>(), 1);
    EXPECT_EQ(summary["scans"]["skipped"]["per_reason"]["malformed"].as<int>(), 2);

    // --strict: the same skip fails the run, and nothing is written.
    fs::remove_all(path("out"));
    const RunResult strict =
        runOffline("--bag " + path("in.bag") + " --out " + path("out") + " --strict");
    EXPECT_EQ(strict.code, 1) << strict.output;
    EXPECT_NE(strict.output.find("error: skipped 2 of 40"), std::string::npos) << strict.output;
    EXPECT_FALSE(fs::exists(path("out/labels.bag")));
  }
}

// The recording starts before its odometry (a driver up before TF): those scans are skipped,
// per topic, and the rest mapped.
TEST_F(OfflineEndToEnd, ScansBeforeTheFirstTransformAreSkipped) {
  BagShape shape;
  shape.tf_from = kStart + 0.375;  // scans at 1000.0-1000.35 (4 per lidar) precede it
  writeRobotBag(path("in.bag"), shape);
  const RunResult run = runOffline("--bag " + path("in.bag") + " --out " + path("out"));
  ASSERT_EQ(run.code, 0) << run.output;
  expectOutputs(path("out"));
  EXPECT_NE(run.output.find("skipped 8 of 40 scans have no transform into the fixed frame at "
                            "their stamp (no_transform): /scan_front: 4 of 20; /scan_rear: 4 of "
                            "20;"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(labelMessages(path("out/labels.bag")), 32u);
  const YAML::Node summary = YAML::LoadFile(path("out/summary.json"));
  EXPECT_EQ(summary["scans"]["skipped"]["per_topic"]["/scan_front"]["no_transform"].as<int>(), 4);
  EXPECT_EQ(summary["scans"]["per_topic"]["/scan_front"].as<int>(), 16);
}

// Every kind of malformed scan the issue lists, once each: all skipped under one reason.
TEST_F(OfflineEndToEnd, MalformedScansOfEveryKindAreSkipped) {
  BagShape shape;
  shape.edit = [](int i, bool rear, sensor_msgs::LaserScan& scan) {
    if (rear) return;
    if (i == 2) scan.angle_increment = 0.0f;
    if (i == 4) std::swap(scan.range_min, scan.range_max);
    if (i == 6) scan.ranges.clear();
    if (i == 8) scan.header.frame_id.clear();
    if (i == 10) scan.ranges.push_back(1.0f);  // one more range than its angles
  };
  writeRobotBag(path("in.bag"), shape);
  const RunResult run = runOffline("--bag " + path("in.bag") + " --out " + path("out"));
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(
      run.output.find("skipped 5 of 40 scans are malformed (malformed): /scan_front: 5 of 20;"),
      std::string::npos)
      << run.output;
  EXPECT_EQ(labelMessages(path("out/labels.bag")), 35u);
}

// A TF glitch puts the robot 370 m away for half a second: its scans are skipped as pose jumps
// and the map stays the room's size (it took 2.2 GB when the jump was mapped).
TEST_F(OfflineEndToEnd, APoseJumpIsSkippedAndNeverGrowsTheMap) {
  BagShape shape;
  // Between odom samples (every 20 ms from 999.8 s): scans at 1000.8-1001.25 s jump.
  shape.jump_from = kStart + 0.785;
  shape.jump_to = kStart + 1.285;
  writeRobotBag(path("in.bag"), shape);
  const RunResult run = runOffline("--bag " + path("in.bag") + " --out " + path("out"));
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("(pose_jump): /scan_front: 5 of 20; /scan_rear: 5 of 20;"),
            std::string::npos)
      << run.output;
  const YAML::Node summary = YAML::LoadFile(path("out/summary.json"));
  EXPECT_LT(summary["map"]["size_m"][0].as<double>(), 30.0);
  EXPECT_EQ(summary["scans"]["skipped"]["per_reason"]["pose_jump"].as<int>(), 10);
}

// Bytes of a LaserScan whose intensities claim 1,415,586,763 elements (the mutation
// that took 5.5 GB), and a scan larger than any beam count needs: skipped, nothing allocated
// from their lengths.
TEST_F(OfflineEndToEnd, CorruptLengthsAndOversizedScansAreSkippedUnread) {
  const float kMarker = 12345.678f;
  BagShape shape;
  shape.edit = [&](int i, bool rear, sensor_msgs::LaserScan& scan) {
    if (rear && i == 7) scan.intensities.assign(3, kMarker);
    if (rear && i == 12) scan.ranges.assign(kHugeBeams, 1.0f);
  };
  writeRobotBag(path("in.bag"), shape);
  // Patch the intensities' length in place: the uint32 just before the marker floats.
  std::string bytes;
  {
    std::ifstream in(path("in.bag"), std::ios::binary);
    std::ostringstream all;
    all << in.rdbuf();
    bytes = all.str();
  }
  std::string pattern(reinterpret_cast<const char*>(&kMarker), sizeof(kMarker));
  const uint32_t three = 3;
  pattern = std::string(reinterpret_cast<const char*>(&three), 4) + pattern;
  const size_t at = bytes.find(pattern);
  ASSERT_NE(at, std::string::npos);
  const uint32_t huge = 1415586763u;
  bytes.replace(at, 4, std::string(reinterpret_cast<const char*>(&huge), 4));
  std::ofstream(path("corrupt.bag"), std::ios::binary) << bytes;

  const RunResult run = runOffline("--bag " + path("corrupt.bag") + " --out " + path("out"));
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("(undecodable): /scan_rear: 1 of 20;"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("intensities claims 1415586763 elements"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("(oversized): /scan_rear: 1 of 20;"), std::string::npos) << run.output;
  EXPECT_EQ(labelMessages(path("out/labels.bag")), 38u);
}

// A recording cut short loses rosbag's index: the message says how to get it back.
TEST_F(OfflineEndToEnd, ATruncatedBagSaysHowToRecoverIt) {
  writeRobotBag(path("in.bag"), true);
  const uintmax_t size = fs::file_size(path("in.bag"));
  fs::resize_file(path("in.bag"), size - size / 1000);  // 99.9 % of it
  const RunResult run = runOffline("--bag " + path("in.bag") + " --out " + path("out"));
  EXPECT_EQ(run.code, 1) << run.output;
  EXPECT_NE(run.output.find("rosbag reindex " + path("in.bag")), std::string::npos) << run.output;
}

// Nothing usable at all: the run fails and names every reason.
TEST_F(OfflineEndToEnd, NothingUsableFails) {
  BagShape shape;
  shape.edit = [](int, bool, sensor_msgs::LaserScan& scan) { scan.angle_increment = 0.0f; };
  writeRobotBag(path("in.bag"), shape);
  const RunResult run = runOffline("--bag " + path("in.bag") + " --out " + path("out"));
  EXPECT_EQ(run.code, 1) << run.output;
  EXPECT_NE(run.output.find("no scan of"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("40 of 40 scans are malformed"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("out/labels.bag")));
}

TEST_F(OfflineEndToEnd, ClearErrors) {
  writeRobotBag(path("in.bag"), true);
  const std::string out = " --out " + path("out");

  RunResult run = runOffline("--bag " + path("in.bag") + out + " --scan-topics /nope,/nada");
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("none of the scan topics /nope, /nada"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("/scan_front"), std::string::npos) << run.output;  // what exists

  run = runOffline("--bag " + path("in.bag") + out + " --scan-topics /tf");
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("not a sensor_msgs/LaserScan"), std::string::npos) << run.output;

  run = runOffline("--bag " + path("missing.bag") + out);
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("cannot read bag"), std::string::npos) << run.output;

  std::ofstream(path("garbage.bag")) << "this is not a bag\n";
  run = runOffline("--bag " + path("garbage.bag") + out);
  EXPECT_EQ(run.code, 1);
  EXPECT_NE(run.output.find("cannot read bag"), std::string::npos) << run.output;

  std::ofstream(path("bad.yaml")) << "theta_bins: 3\n";
  run = runOffline("--bag " + path("in.bag") + out + " --params " + path("bad.yaml"));
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.output.find("theta_bins"), std::string::npos) << run.output;

  std::ofstream(path("bad2.yaml")) << "penetration_tolerance: far\n";
  run = runOffline("--bag " + path("in.bag") + out + " --params " + path("bad2.yaml"));
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.output.find("penetration_tolerance"), std::string::npos) << run.output;

  run = runOffline("--bag " + path("in.bag") + out + " --params " + path("none.yaml"));
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.output.find("none.yaml"), std::string::npos) << run.output;

  run = runOffline("--bag " + path("in.bag") + " --fixed-frame");
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.output.find("--fixed-frame needs a value"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("Usage"), std::string::npos) << run.output;

  run = runOffline("--help");
  EXPECT_EQ(run.code, 0);
  EXPECT_NE(run.output.find("--scan-topics"), std::string::npos);

  EXPECT_FALSE(fs::exists(path("out/labels.bag")));
}

TEST_F(OfflineEndToEnd, RealStationaryRecording) {
  const std::string bag = RFM_SHARED_DATA_DIR "/real/demo_stationary_simple_environment.bag";
  if (!fs::is_regular_file(bag)) GTEST_SKIP() << bag << " is not there";
  const std::string out = path("out");
  const RunResult run =
      runOffline("--bag " + bag + " --out " + out + " --fixed-frame laser --scan-topics /scan");
  ASSERT_EQ(run.code, 0) << run.output;
  expectOutputs(out);
  rosbag::Bag labels_bag(out + "/labels.bag");
  rosbag::View view(labels_bag);
  EXPECT_EQ(view.size(), 1265u);
  for (const rosbag::MessageInstance& m : view) {
    const auto labels = m.instantiate<reflectance_field_map::RayLabels>();
    ASSERT_TRUE(labels);
    ASSERT_EQ(labels->labels.size(), 512u);
    EXPECT_EQ(labels->header.frame_id, "laser");
    EXPECT_EQ(labels->scan_topic, "/scan");
    break;
  }
  const YAML::Node summary = YAML::LoadFile(out + "/summary.json");
  EXPECT_EQ(summary["scans"]["total"].as<int>(), 1265);
  EXPECT_EQ(summary["rays"].as<int>(), 1265 * 512);
}

}  // namespace
