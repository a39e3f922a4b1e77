// Moving people: diffuse discs walking waypoint paths with optional pauses, appearing and leaving
// the scene at given times. ROS-free.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "reflectance_field_map/sim/world.h"

namespace rfm::sim {

struct PersonWaypoint {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double pause = 0.0;  // seconds spent standing here before walking on
};

struct PersonSpec {
  std::string name;
  double radius = 0.25;
  double speed = 1.2;       // walking speed, m/s
  double start_time = 0.0;  // appears at the first waypoint (scene time, s)
  double end_time = std::numeric_limits<double>::infinity();  // disappears at the latest here
  bool loop = false;  // walk back to the first waypoint and repeat; otherwise leave at the end
  std::vector<PersonWaypoint> waypoints;
};

class Pedestrian {
 public:
  // Throws std::invalid_argument for fewer than one waypoint or non-positive radius or speed.
  explicit Pedestrian(PersonSpec spec);

  // Centre at scene time t, or nothing when the person is not in the scene.
  std::optional<Eigen::Vector2d> positionAt(double t) const;
  const PersonSpec& spec() const { return spec_; }
  // Time the person needs for one pass (or one loop) of the path, pauses included.
  double cycleDuration() const { return cycle_duration_; }

 private:
  struct Leg {  // pause at `from`, then walk to `to`
    Eigen::Vector2d from, to;
    double pause, walk;
  };
  PersonSpec spec_;
  std::vector<Leg> legs_;
  double cycle_duration_ = 0.0;
};

// The discs of all people present at time t.
std::vector<Circle> peopleAt(const std::vector<Pedestrian>& people, double t);

}  // namespace rfm::sim
