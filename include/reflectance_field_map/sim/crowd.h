// Random people for procedural scenes: walkers who pause, people who stand a while and leave,
// pairs and trios walking side by side, groups standing in conversation, and passers-by in the
// street. Every walk is planned around walls and panes, and no two people, nor a person and the
// robot, ever overlap. ROS-free.
#pragma once

#include <vector>

#include "reflectance_field_map/sim/floor_plan.h"
#include "reflectance_field_map/sim/navigation_grid.h"
#include "reflectance_field_map/sim/people.h"
#include "reflectance_field_map/sim/random_draws.h"
#include "reflectance_field_map/sim/trajectory.h"
#include "reflectance_field_map/sim/world.h"

namespace rfm::sim {

struct CrowdSetting {
  const World& world;
  const NavigationGrid& grid;
  const FloorPlan& plan;
  const RobotTrajectory& robot;
  double duration = 60.0;
};

// How close the robot's centre may come to a person's footprint, m (a wheelchair with its
// lidars, about 0.65 m from its centre to its farthest corner).
constexpr double kRobotFootprintRadius = 0.65;

// People drawn from `dice`: about one per 30 m^2 of floor, plus passers-by outside a facade.
std::vector<PersonSpec> generateCrowd(Dice& dice, const CrowdSetting& setting);

}  // namespace rfm::sim
