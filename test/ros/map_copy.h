// What the node-level tests share: waiting for a condition with a deadline, and a local copy of
// /rfm/map kept current with /rfm/map_updates, as a navigation stack's static layer keeps it.
#pragma once

#include <gtest/gtest.h>
#include <map_msgs/OccupancyGridUpdate.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <mutex>

namespace rfm_test {

// Waits (spinning in the background) until `done` holds or `seconds` of wall time pass.
inline bool waitFor(const std::function<bool()>& done, double seconds) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < deadline) {
    if (done()) return true;
    ros::WallDuration(0.01).sleep();  // polling interval, not synchronisation
  }
  return done();
}

// A local copy of /rfm/map kept current with /rfm/map_updates.
struct MapCopy {
  std::mutex mutex;
  nav_msgs::OccupancyGrid grid;
  ros::Time last_full;    // header stamp of the last full map
  ros::Time last_change;  // header stamp of the last full map or update
  int full_maps = 0;
  int full_maps_same_bounds = 0;  // full maps whose geometry equals the one before
  int updates = 0;

  void onMap(const nav_msgs::OccupancyGridConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex);
    const nav_msgs::MapMetaData& before = grid.info;
    const nav_msgs::MapMetaData& now = msg->info;
    if (full_maps > 0 && now.width == before.width && now.height == before.height &&
        now.origin.position.x == before.origin.position.x &&
        now.origin.position.y == before.origin.position.y) {
      ++full_maps_same_bounds;
    }
    grid = *msg;
    last_full = msg->header.stamp;
    last_change = std::max(last_change, msg->header.stamp);
    ++full_maps;
  }
  void onUpdate(const map_msgs::OccupancyGridUpdateConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex);
    ASSERT_LE(msg->x + msg->width, grid.info.width);
    ASSERT_LE(msg->y + msg->height, grid.info.height);
    for (uint32_t y = 0; y < msg->height; ++y) {
      for (uint32_t x = 0; x < msg->width; ++x) {
        grid.data[(msg->y + y) * grid.info.width + msg->x + x] = msg->data[y * msg->width + x];
      }
    }
    last_change = std::max(last_change, msg->header.stamp);
    ++updates;
  }
  // Occupancy at a world point (-2 outside the grid).
  int at(double wx, double wy) {
    std::lock_guard<std::mutex> lock(mutex);
    return atLocked(wx, wy);
  }
  int atLocked(double wx, double wy) const {
    if (grid.info.width == 0) return -2;
    const int x =
        static_cast<int>(std::floor((wx - grid.info.origin.position.x) / grid.info.resolution));
    const int y =
        static_cast<int>(std::floor((wy - grid.info.origin.position.y) / grid.info.resolution));
    if (x < 0 || y < 0 || x >= static_cast<int>(grid.info.width) ||
        y >= static_cast<int>(grid.info.height)) {
      return -2;
    }
    return grid.data[y * grid.info.width + x];
  }
  // Occupied anywhere within one cell of (wx, wy).
  bool occupiedNear(double wx, double wy) {
    std::lock_guard<std::mutex> lock(mutex);
    const double r = grid.info.resolution;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (atLocked(wx + dx * r, wy + dy * r) == 100) return true;
      }
    }
    return false;
  }
  ros::Time lastChange() {
    std::lock_guard<std::mutex> lock(mutex);
    return last_change;
  }
  int countOccupied() {
    std::lock_guard<std::mutex> lock(mutex);
    return static_cast<int>(std::count(grid.data.begin(), grid.data.end(), 100));
  }
  nav_msgs::OccupancyGrid copy() {
    std::lock_guard<std::mutex> lock(mutex);
    return grid;
  }
};

}  // namespace rfm_test
