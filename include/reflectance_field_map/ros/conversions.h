#pragma once

#include "reflectance_field_map/RayLabels.h"
#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/mapper.h"

#include <geometry_msgs/Quaternion.h>
#include <geometry_msgs/Transform.h>
#include <map_msgs/OccupancyGridUpdate.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/ColorRGBA.h>
#include <tf2/buffer_core.h>
#include <visualization_msgs/Marker.h>

#include <string>
#include <vector>

// Free conversion functions between ROS messages and the ROS-free core types.
namespace rfm::ros_glue {

// A frame id as tf2 takes it: without leading slashes ("/odom" -> "odom").
std::string tf2FrameId(const std::string& frame);

// Yaw (rotation about z, REP-103) of a quaternion; the quaternion need not be normalised.
double yawFromQuaternion(const geometry_msgs::Quaternion& q);

// A 3D transform projected on the plane: position (x, y) and yaw from the quaternion.
rfm::Pose2D toPose2D(const geometry_msgs::Transform& transform);

// A laser's pose in the plane. A laser mounted upside down (its z axis pointing down) sweeps
// clockwise seen from above: its scan is mirrored (see toLaserScan2D) and `pose.yaw` is the
// heading of its x axis.
struct PlanarSensorPose {
  rfm::Pose2D pose;
  bool upside_down = false;
};
PlanarSensorPose toPlanarSensorPose(const geometry_msgs::Transform& transform);

// Whether the message's beams go clockwise in the laser's frame (angle_increment < 0), as some
// drivers publish them.
bool isClockwise(const sensor_msgs::LaserScan& msg);

// sensor_msgs/LaserScan -> core scan, which sweeps counter-clockwise in the plane: a clockwise
// message's beams are reversed, and with `upside_down` the beams are reversed (again) and their
// angles negated. Labels computed on it come back to message order through toMessageOrder().
rfm::LaserScan2D toLaserScan2D(const sensor_msgs::LaserScan& msg, bool upside_down = false);
// Whether the core scan holds the message's beams in reverse order: the message is clockwise or
// the laser upside down, not both.
bool reversesBeamOrder(const sensor_msgs::LaserScan& msg, bool upside_down);
std::vector<rfm::RayLabel> toMessageOrder(std::vector<rfm::RayLabel> labels, bool reversed);

// When the scan's last beam was measured (its stamp + rfm::sweepSeconds): exactly its stamp when
// the message gives no sweep (time_increment 0).
ros::Time sweepEnd(const sensor_msgs::LaserScan& msg);

// Turns the beams of `scan` (placed at `scan.sensor_pose`, the pose of `frame` at the scan's
// stamp) as the sensor turned during its sweep and moves its returns as the sensor moved
// (rfm::compensateSweepMotion), from TF's pose of `frame` at `sweep_end`. `beam0_last`: the beams
// are in the reverse of their measured order. False, changing nothing, when `sweep_end` is `stamp`
// or TF has no pose for it.
bool compensateSweepFromTf(const tf2::BufferCore& tf, const std::string& fixed_frame,
                           const std::string& frame, const ros::Time& stamp,
                           const ros::Time& sweep_end, bool beam0_last, rfm::TimedScan& scan);

// The scan with every MOTION and REFLECTION beam set to +inf (REP-117: no return); `labels`
// in message order, one per beam (beams without a label are left as they are).
sensor_msgs::LaserScan filterScan(const sensor_msgs::LaserScan& scan,
                                  const std::vector<rfm::RayLabel>& labels);

reflectance_field_map::RayLabels toRayLabelsMsg(const std_msgs::Header& header,
                                                const std::string& topic,
                                                const std::vector<rfm::RayLabel>& labels);

// Occupancy values (-1/0/100, rfm::occupancyValue) of `box`, row-major, x fastest.
void toOccupancyData(const rfm::GlobalMap2D& map, const rfm::CellBox& box,
                     std::vector<int8_t>& data);

// The cells of `box` as an OccupancyGrid in `frame` (origin at the box's lower-left corner).
nav_msgs::OccupancyGrid toOccupancyGrid(const rfm::GlobalMap2D& map, const rfm::CellBox& box,
                                        double resolution, const std::string& frame,
                                        const ros::Time& stamp);

// The cells of `window` as an update of a grid published over `grid_box` (window inside it).
map_msgs::OccupancyGridUpdate toOccupancyGridUpdate(const rfm::GlobalMap2D& map,
                                                    const rfm::CellBox& window,
                                                    const rfm::CellBox& grid_box,
                                                    const std::string& frame,
                                                    const ros::Time& stamp);

// Fig. 1 of the paper: glass blue, metal red, motion magenta, static green, reflections cyan.
std_msgs::ColorRGBA classColor(rfm::CellClass cell_class);

// One CUBE_LIST with a cube per cell of `cell_class` in `box` (action DELETE when there is
// none), namespace `ns`, coloured by classColor().
visualization_msgs::Marker toCubeList(const rfm::GlobalMap2D& map, const rfm::CellBox& box,
                                      rfm::CellClass cell_class, double resolution,
                                      const std::string& frame, const ros::Time& stamp,
                                      const std::string& ns, int id);

// Same from an already extracted box (rfm::GlobalMap2D::extract), for several classes at once.
visualization_msgs::Marker toCubeList(const std::vector<rfm::CellClass>& cells,
                                      const rfm::CellBox& box, rfm::CellClass cell_class,
                                      double resolution, const std::string& frame,
                                      const ros::Time& stamp, const std::string& ns, int id);

}  // namespace rfm::ros_glue
