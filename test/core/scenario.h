#pragma once

// Drives a Mapper through a synthetic world the way the node does: scans at 40 Hz, motion
// removal on a 2 Hz "timer".

#include "reflectance_field_map/core/mapper.h"

#include "synthetic_world.h"

#include <functional>
#include <vector>

namespace rfm {
namespace testing {

struct ScenarioStep {
  Pose2D robot;
  std::vector<Disc> people;
};

inline MapperOptions scenarioOptions() {
  MapperOptions options;
  options.active_region.active_region_radius = 10.0;
  return options;
}

// Runs the steps; returns every scan inserted (for labelling afterwards).
inline std::vector<TimedScan> runScenario(Mapper& mapper, SyntheticWorld& world,
                                          const std::vector<ScenarioStep>& steps,
                                          int scans_per_motion_removal = 20) {
  std::vector<TimedScan> scans;
  for (size_t i = 0; i < steps.size(); ++i) {
    world.people = steps[i].people;
    TimedScan scan = world.timedScan(steps[i].robot, 0.025 * i);
    mapper.addScan(scan);
    scans.push_back(std::move(scan));
    if ((i + 1) % scans_per_motion_removal == 0) mapper.removeMotion();
  }
  mapper.removeMotion();
  return scans;
}

// A straight drive at wheelchair speed (1 m/s) scanned at 40 Hz, heading `yaw`: the density of
// views the defaults are tuned for.
inline std::vector<ScenarioStep> driveBy(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                         double yaw) {
  const int steps = std::max(2, static_cast<int>(std::round((to - from).norm() / 0.025)) + 1);
  std::vector<ScenarioStep> out;
  for (const Pose2D& pose : straightPath(from, to, steps, yaw))
    out.push_back({pose, {}});
  return out;
}

// Fraction of the cells along a segment (either side of it) with one of the classes.
inline double fractionAlong(const Mapper& mapper, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b, std::function<bool(CellClass)> accept) {
  const GridGeometry& g = mapper.field().geometry();
  const Eigen::Vector2d u = (b - a).normalized();
  const Eigen::Vector2d n(-u.y(), u.x());
  int total = 0, accepted = 0;
  for (double s = 0.0; s <= (b - a).norm(); s += g.resolution()) {
    const Eigen::Vector2d p = a + s * u;
    ++total;
    accepted += accept(mapper.cellClass(g.cellOf(p + 1e-3 * n))) ||
                accept(mapper.cellClass(g.cellOf(p - 1e-3 * n)));
  }
  return total == 0 ? 0.0 : static_cast<double>(accepted) / total;
}

// How many beams got each label.
struct LabelCounts {
  size_t kept = 0, motion = 0, reflection = 0, no_return = 0;
};

inline LabelCounts countLabels(const std::vector<std::vector<RayLabel>>& labels) {
  LabelCounts c;
  for (const auto& scan : labels) {
    for (RayLabel l : scan) {
      c.kept += l == RayLabel::kKept;
      c.motion += l == RayLabel::kMotion;
      c.reflection += l == RayLabel::kReflection;
      c.no_return += l == RayLabel::kNoReturn;
    }
  }
  return c;
}

// A room 8 m x 6 m with a framed pane across its west half, parallel to the robot's paths.
inline SyntheticWorld roomWithPane() {
  SyntheticWorld world;
  world.addWall({-4.0, -3.0}, {4.0, -3.0});
  world.addWall({4.0, -3.0}, {4.0, 3.0});
  world.addWall({4.0, 3.0}, {-4.0, 3.0});
  world.addWall({-4.0, 3.0}, {-4.0, -3.0});
  world.addFramedPane({-3.0, 0.0}, {0.0, 0.0});  // parallel to the robot's paths
  return world;
}

// A framed glass pane 2 m from the line x = 0 with a wall 2 m behind it, and the robot's drive
// along that line facing the pane, 8 m long.
inline SyntheticWorld paneWithWallBehindWorld() {
  SyntheticWorld world;
  world.addFramedPane({2.0, -3.0}, {2.0, 3.0});
  world.addWall({4.0, -6.0}, {4.0, 6.0});
  return world;
}
inline std::vector<ScenarioStep> driveAlongThePane() {
  return driveBy({0.0, -4.0}, {0.0, 4.0}, kPi / 2);
}

// The scans of the drive along the pane; `sensors` lidars take turns, each at 40 Hz.
inline std::vector<TimedScan> paneWithWallBehind(int sensors) {
  const SyntheticWorld world = paneWithWallBehindWorld();
  std::vector<TimedScan> scans;
  for (const auto& step : driveAlongThePane()) {
    scans.push_back(world.timedScan(step.robot, 0.025 / sensors * scans.size()));
    scans.back().sensor_id = static_cast<uint32_t>(scans.size() % sensors);
  }
  return scans;
}

}  // namespace testing
}  // namespace rfm
