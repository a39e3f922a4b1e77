// Random floor plans for procedural scenes: rooms off a corridor or a recursively divided hall,
// doors, glass fronts and facades (framed panes with mullions), curved glass, freestanding panes,
// glass meeting boxes, mirrors, metal doors and cladding, pillars, tables and cabinets, and the
// street seen through a facade. ROS-free.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "reflectance_field_map/sim/random_draws.h"
#include "reflectance_field_map/sim/scene_description.h"

namespace rfm::sim {

struct FloorPlanArea {
  Eigen::Vector2d low, high;
  bool outside = false;  // the street beyond a facade (people only; the robot stays in)
};

struct FloorPlan {
  std::string summary;  // what was built, in a few words
  Eigen::Vector2d building_low = Eigen::Vector2d::Zero(), building_high = Eigen::Vector2d::Zero();
  Eigen::Vector2d world_low = Eigen::Vector2d::Zero(), world_high = Eigen::Vector2d::Zero();
  std::vector<FloorPlanArea> areas;  // rooms, halls, corridors, and the street if any
  std::vector<WallDescription> walls;
};

// A random building drawn from `dice`, in [0, W] x [0, H] with W in [14, 30] m, H in [10, 22] m.
FloorPlan generateFloorPlan(Dice& dice);

}  // namespace rfm::sim
