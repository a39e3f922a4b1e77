#pragma once

// A realistic indoor floor for benchmarks: offices off a corridor, a glass-fronted meeting
// room, furniture, two Hokuyo UTM-30LX scans per pose (front and rear), a few percent of
// no-returns. Built on the core tests' ray caster.

#include "synthetic_world.h"

#include <random>

namespace rfm {
namespace benchmarking {

inline testing::SyntheticWorld indoorFloor() {
  testing::SyntheticWorld world;
  // Corridor 3 m wide along x, 30 m long.
  world.addWall({-15.0, -1.5}, {15.0, -1.5});
  world.addWall({-15.0, 1.5}, {-2.0, 1.5});
  world.addFramedPane({-2.0, 1.5}, {4.0, 1.5});  // glass front of a meeting room
  world.addWall({4.0, 1.5}, {15.0, 1.5});
  // Offices on the south side: 4 m deep, doors 1 m wide.
  for (double x = -15.0; x < 15.0; x += 5.0) {
    world.addWall({x, -1.5}, {x, -5.5});
    world.addWall({x + 1.2, -1.5}, {x + 1.2, -1.6});
  }
  world.addWall({-15.0, -5.5}, {15.0, -5.5});
  // Meeting room and offices to the north, 6 m deep.
  world.addWall({-15.0, 7.5}, {15.0, 7.5});
  world.addWall({-2.0, 1.5}, {-2.0, 7.5});
  world.addWall({4.0, 1.5}, {4.0, 7.5});
  // Furniture: tables and cabinets.
  for (double x = -12.0; x < 14.0; x += 5.0) {
    world.addWall({x, -4.0}, {x + 1.6, -4.0});
    world.addWall({x + 1.6, -4.0}, {x + 1.6, -4.8});
  }
  world.addWall({-0.5, 4.0}, {2.5, 4.0});
  world.addWall({2.5, 4.0}, {2.5, 5.0});
  return world;
}

struct BenchmarkScan {
  TimedScan scan;
  std::vector<Ray> rays;
};

// Front and rear scans of `beams` over 270 deg at 40 Hz along the corridor at 1 m/s (wheelchair
// speed), with ~3 % random no-returns.
inline std::vector<BenchmarkScan> indoorScans(int poses, const InsertionOptions& insertion,
                                              int beams = 1081) {
  testing::SyntheticWorld world = indoorFloor();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<BenchmarkScan> scans;
  for (int i = 0; i < poses; ++i) {
    const double s = static_cast<double>(i) / poses;
    const double length = 0.025 * poses;  // 1 m/s at 40 Hz
    const Pose2D robot{{-0.5 * length + length * s, 0.3 * std::sin(6.0 * s)},
                       0.2 * std::sin(9.0 * s)};
    for (const Pose2D& mount : {Pose2D{{0.35, 0.0}, 0.0}, Pose2D{{-0.35, 0.0}, kPi}}) {
      BenchmarkScan b;
      b.scan.stamp = 0.0125 * static_cast<double>(scans.size());
      b.scan.robot_pose = robot;
      b.scan.sensor_pose = robot.compose(mount);
      b.scan.scan = world.scan(b.scan.sensor_pose, beams);
      for (float& r : b.scan.scan.ranges) {
        if (unit(rng) < 0.03) r = std::numeric_limits<float>::infinity();
      }
      scanToRays(b.scan.scan, b.scan.sensor_pose, insertion, b.rays);
      scans.push_back(std::move(b));
    }
  }
  return scans;
}

}  // namespace benchmarking
}  // namespace rfm
