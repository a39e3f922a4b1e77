// The simulator must not be kind to mappers: a plain occupancy grid built from a shipped glass
// scene has to show the paper's gap (Table II): most glass erased, many reflections kept, while
// diffuse walls are kept. A reference grid is built here from the simulated scans.
#include <gtest/gtest.h>

#include <cmath>

#include "reflectance_field_map/sim/evaluation.h"
#include "reflectance_field_map/sim/scene.h"
#include "reflectance_field_map/sim/simulator.h"

namespace rfm::sim {
namespace {

// Minimal log-odds occupancy grid (5 cm) with sampled ray traversal, as a typical 2D mapper
// builds it: misses stop 10 cm short of the endpoint and a beam counts as kept when its endpoint
// is within one cell of an occupied cell, so range noise alone does not erase walls. Not the
// project's mapper.
class ReferenceOccupancyGrid {
 public:
  ReferenceOccupancyGrid(Eigen::Vector2d low, double size, double resolution)
      : low_(low),
        resolution_(resolution),
        width_(static_cast<int>(size / resolution)),
        cells_(static_cast<std::size_t>(width_) * width_, 0.0f) {}

  void insert(const Eigen::Vector2d& origin, const Eigen::Vector2d& end) {
    const double length = (end - origin).norm();
    const double free_length = length - 0.1;
    const Eigen::Vector2d direction = (end - origin) / length;
    const long end_cell = cell(end);
    for (double s = 0.0; s < free_length; s += resolution_ * 0.5) {
      const long c = cell(origin + s * direction);
      if (c >= 0 && c != end_cell) cells_[c] = std::max(-2.0f, cells_[c] - 0.4f);
    }
    if (end_cell >= 0) cells_[end_cell] = std::min(3.5f, cells_[end_cell] + 0.85f);
  }
  bool occupiedNear(const Eigen::Vector2d& point) const {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const long c = cell(point + resolution_ * Eigen::Vector2d(dx, dy));
        if (c >= 0 && cells_[c] > 0.0f) return true;
      }
    }
    return false;
  }

 private:
  long cell(const Eigen::Vector2d& p) const {
    const int x = static_cast<int>(std::floor((p.x() - low_.x()) / resolution_));
    const int y = static_cast<int>(std::floor((p.y() - low_.y()) / resolution_));
    if (x < 0 || y < 0 || x >= width_ || y >= width_) return -1;
    return static_cast<long>(y) * width_ + x;
  }
  Eigen::Vector2d low_;
  double resolution_;
  int width_;
  std::vector<float> cells_;
};

struct Recorder : SimulationSink {
  void onRobotState(double time, const RobotState& state, const Pose2&) override {
    states.emplace_back(time, state);
  }
  void onScan(const SimScan& scan, const LidarSpec&) override { scans.push_back(scan); }
  Pose2 poseAt(double t) const {  // states are dense (100 Hz): nearest earlier sample is enough
    auto it = std::lower_bound(states.begin(), states.end(), t - 1e-9,
                               [](const auto& s, double time) { return s.first < time; });
    return it->second.pose;
  }
  std::vector<std::pair<double, RobotState>> states;
  std::vector<SimScan> scans;
};

TEST(SceneDifficultyTest, PlainOccupancyGridErasesGlassAndKeepsReflections) {
  Scene scene = loadScene(std::string(RFM_SCENE_DIR) + "/atrium.yaml");
  scene.duration = 40.0;  // half the ring corridor keeps the test short
  Simulator simulator(scene, scene.seed);
  Recorder recorder;
  simulator.run(recorder);

  ReferenceOccupancyGrid grid(Eigen::Vector2d(-40, -40), 80.0, 0.05);
  auto endpoints = [&](const SimScan& scan, auto&& visit) {
    const LidarSpec& lidar = scene.lidars[scan.lidar_index];
    const Pose2 laser = recorder.poseAt(scan.time).compose(lidar.mount());
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      if (!std::isfinite(scan.ranges[i])) continue;
      const double angle = laser.yaw + lidar.beamAngle(static_cast<int>(i));
      visit(i, laser.position(),
            laser.position() + scan.ranges[i] * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
  };
  // Build from every other scan, score a disjoint subset (every fourth scan) against the grid.
  for (std::size_t s = 0; s < recorder.scans.size(); s += 2) {
    endpoints(recorder.scans[s], [&](std::size_t, const Eigen::Vector2d& origin,
                                     const Eigen::Vector2d& end) { grid.insert(origin, end); });
  }
  ConfusionMatrix matrix;
  for (std::size_t s = 1; s < recorder.scans.size(); s += 4) {
    const SimScan& scan = recorder.scans[s];
    std::vector<std::uint8_t> labels(scan.ranges.size(), 0);
    endpoints(scan, [&](std::size_t i, const Eigen::Vector2d&, const Eigen::Vector2d& end) {
      labels[i] = grid.occupiedNear(end) ? 1 : 3;
    });
    matrix.addScan(scan.classes, labels);
  }
  std::cout << matrix.toMarkdownTable();
  EXPECT_GT(matrix.row(0).keptPercent(), 90.0);  // diffuse walls survive
  EXPECT_LT(matrix.row(1).keptPercent(), 70.0);  // glass mostly erased
  EXPECT_GT(matrix.row(4).keptPercent(), 15.0);  // many reflections kept
  EXPECT_GT(matrix.row(1).total, 10000u);
  EXPECT_GT(matrix.row(3).total, 5000u);
}

}  // namespace
}  // namespace rfm::sim
