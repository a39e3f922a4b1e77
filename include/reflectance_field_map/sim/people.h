// Moving people: diffuse discs (or pairs of legs) walking waypoint paths with optional pauses,
// appearing and leaving the scene at given times. ROS-free.
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
  // The person's footprint: walls and panes must stay this far from the path. With `legs` it
  // bounds the legs, which the lidar sees at its height instead of one disc.
  double radius = 0.25;
  bool legs = false;
  double leg_radius = 0.06;
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
  // What the lidar sees of the person at time t (a disc, or two legs), appended to `out`.
  void appendBody(double t, std::vector<Circle>& out) const;
  // Farthest a leg reaches from the centre while walking (0 without legs).
  double legReach() const;
  const PersonSpec& spec() const { return spec_; }
  // Time the person needs for one pass (or one loop) of the path, pauses included.
  double cycleDuration() const { return cycle_duration_; }

 private:
  struct Leg {  // pause at `from`, then walk to `to`
    Eigen::Vector2d from, to;
    double pause, walk;
  };
  // Distance walked along the path by time t (t inside the person's presence).
  double distanceAt(double t) const;
  // Point of the path `distance` metres from its start (wrapping round a loop), and the unit
  // direction of travel there.
  std::pair<Eigen::Vector2d, Eigen::Vector2d> pathPointAt(double distance) const;
  double stride() const;

  PersonSpec spec_;
  std::vector<Leg> legs_;
  double cycle_duration_ = 0.0;
  double path_length_ = 0.0;
};

// What the lidar sees of all people present at time t (discs and legs).
std::vector<Circle> peopleAt(const std::vector<Pedestrian>& people, double t);

// Where a walk would take a person's footprint (its radius) through a static surface.
struct WallCollision {
  std::size_t waypoint = 0;  // the walk starts at this waypoint
  Eigen::Vector2d from, to;  // the walk
  Eigen::Vector2d at;        // the first centre found overlapping a surface
};

// People are solid: the first walk of `person` (between consecutive waypoints, and back to the
// first when looping) whose footprint, checked every 5 cm, overlaps a wall, pane or pillar.
std::optional<WallCollision> findWallCollision(const PersonSpec& person, const World& world);

}  // namespace rfm::sim
