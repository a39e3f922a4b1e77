#include "reflectance_field_map/ros/conversions.h"

#include <tf2/exceptions.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rfm::ros_glue {

std::string tf2FrameId(const std::string& frame) {
  const size_t start = frame.find_first_not_of('/');
  return start == std::string::npos ? std::string() : frame.substr(start);
}

double yawFromQuaternion(const geometry_msgs::Quaternion& q) {
  // w^2 + x^2 - y^2 - z^2 rather than 1 - 2 (y^2 + z^2): both terms scale with the norm, so
  // their angle holds for a quaternion that is not normalised.
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), q.w * q.w + q.x * q.x - q.y * q.y - q.z * q.z);
}

rfm::Pose2D toPose2D(const geometry_msgs::Transform& transform) {
  rfm::Pose2D pose;
  pose.position = {transform.translation.x, transform.translation.y};
  pose.yaw = yawFromQuaternion(transform.rotation);
  return pose;
}

PlanarSensorPose toPlanarSensorPose(const geometry_msgs::Transform& transform) {
  const geometry_msgs::Quaternion& q = transform.rotation;
  Eigen::Quaterniond rotation(q.w, q.x, q.y, q.z);
  if (rotation.norm() < 1e-9) rotation = Eigen::Quaterniond::Identity();
  const Eigen::Matrix3d r = rotation.normalized().toRotationMatrix();
  PlanarSensorPose out;
  out.pose.position = {transform.translation.x, transform.translation.y};
  // Heading of the x axis projected on the plane (robust to a small tilt and to a flip).
  out.pose.yaw = std::atan2(r(1, 0), r(0, 0));
  out.upside_down = r(2, 2) < 0.0;
  return out;
}

rfm::LaserScan2D toLaserScan2D(const sensor_msgs::LaserScan& msg, bool upside_down) {
  rfm::LaserScan2D scan;
  scan.angle_min = msg.angle_min;
  scan.angle_max = msg.angle_max;
  scan.angle_increment = msg.angle_increment;
  scan.range_min = msg.range_min;
  scan.range_max = msg.range_max;
  scan.ranges = msg.ranges;
  if (isClockwise(msg)) rfm::reverseBeamOrder(scan);
  if (upside_down) rfm::mirrorScan(scan);
  return scan;
}

bool isClockwise(const sensor_msgs::LaserScan& msg) {
  return msg.angle_increment < 0.0f && !msg.ranges.empty();
}

bool reversesBeamOrder(const sensor_msgs::LaserScan& msg, bool upside_down) {
  return isClockwise(msg) != upside_down;
}

std::vector<rfm::RayLabel> toMessageOrder(std::vector<rfm::RayLabel> labels, bool reversed) {
  if (reversed) std::reverse(labels.begin(), labels.end());
  return labels;
}

ros::Time sweepEnd(const sensor_msgs::LaserScan& msg) {
  // Added as a duration: a stamp does not survive a round trip through seconds as a double.
  return msg.header.stamp + ros::Duration(rfm::sweepSeconds(msg.time_increment, msg.ranges.size()));
}

bool compensateSweepFromTf(const tf2::BufferCore& tf, const std::string& fixed_frame,
                           const std::string& frame, const ros::Time& stamp,
                           const ros::Time& sweep_end, bool beam0_last, rfm::TimedScan& scan) {
  if (sweep_end == stamp) return false;
  geometry_msgs::TransformStamped end;
  try {
    end = tf.lookupTransform(fixed_frame, frame, sweep_end);
  } catch (const tf2::TransformException&) {
    return false;  // no pose then (yet, or any more): the scan stays as stamped
  }
  return rfm::compensateSweepMotion(scan.scan, scan.sensor_pose,
                                    toPlanarSensorPose(end.transform).pose, beam0_last);
}

sensor_msgs::LaserScan filterScan(const sensor_msgs::LaserScan& scan,
                                  const std::vector<rfm::RayLabel>& labels) {
  sensor_msgs::LaserScan out = scan;
  const size_t n = std::min(labels.size(), out.ranges.size());
  for (size_t i = 0; i < n; ++i) {
    if (labels[i] == rfm::RayLabel::kMotion || labels[i] == rfm::RayLabel::kReflection) {
      out.ranges[i] = std::numeric_limits<float>::infinity();
      if (i < out.intensities.size()) out.intensities[i] = 0.0f;
    }
  }
  return out;
}

reflectance_field_map::RayLabels toRayLabelsMsg(const std_msgs::Header& header,
                                                const std::string& topic,
                                                const std::vector<rfm::RayLabel>& labels) {
  reflectance_field_map::RayLabels msg;
  msg.header = header;
  msg.scan_topic = topic;
  msg.labels.reserve(labels.size());
  for (rfm::RayLabel label : labels)
    msg.labels.push_back(static_cast<uint8_t>(label));
  return msg;
}

void toOccupancyData(const rfm::GlobalMap2D& map, const rfm::CellBox& box,
                     std::vector<int8_t>& data) {
  std::vector<rfm::CellClass> cells;
  if (!box.empty()) map.extract(box, cells);
  data.resize(cells.size());
  std::transform(cells.begin(), cells.end(), data.begin(),
                 [](rfm::CellClass c) { return rfm::occupancyValue(c); });
}

nav_msgs::OccupancyGrid toOccupancyGrid(const rfm::GlobalMap2D& map, const rfm::CellBox& box,
                                        double resolution, const std::string& frame,
                                        const ros::Time& stamp) {
  nav_msgs::OccupancyGrid grid;
  grid.header.frame_id = frame;
  grid.header.stamp = stamp;
  grid.info.map_load_time = stamp;
  grid.info.resolution = static_cast<float>(resolution);
  grid.info.width = box.empty() ? 0 : static_cast<uint32_t>(box.width());
  grid.info.height = box.empty() ? 0 : static_cast<uint32_t>(box.height());
  grid.info.origin.position.x = box.min.x() * resolution;
  grid.info.origin.position.y = box.min.y() * resolution;
  grid.info.origin.orientation.w = 1.0;
  if (!box.empty()) toOccupancyData(map, box, grid.data);
  return grid;
}

map_msgs::OccupancyGridUpdate toOccupancyGridUpdate(const rfm::GlobalMap2D& map,
                                                    const rfm::CellBox& window,
                                                    const rfm::CellBox& grid_box,
                                                    const std::string& frame,
                                                    const ros::Time& stamp) {
  map_msgs::OccupancyGridUpdate update;
  update.header.frame_id = frame;
  update.header.stamp = stamp;
  const rfm::CellBox box = window.intersect(grid_box);
  if (box.empty()) return update;
  update.x = box.min.x() - grid_box.min.x();
  update.y = box.min.y() - grid_box.min.y();
  update.width = static_cast<uint32_t>(box.width());
  update.height = static_cast<uint32_t>(box.height());
  toOccupancyData(map, box, update.data);
  return update;
}

std_msgs::ColorRGBA classColor(rfm::CellClass cell_class) {
  std_msgs::ColorRGBA color;
  color.a = 1.0f;
  switch (cell_class) {
    case rfm::CellClass::kGlass:  // blue
      color.r = 0.1f;
      color.g = 0.35f;
      color.b = 1.0f;
      break;
    case rfm::CellClass::kMetal:  // red
      color.r = 1.0f;
      color.g = 0.1f;
      color.b = 0.1f;
      break;
    case rfm::CellClass::kMotion:  // magenta
      color.r = 1.0f;
      color.g = 0.0f;
      color.b = 1.0f;
      break;
    case rfm::CellClass::kStatic:  // green
    case rfm::CellClass::kOccupied:
      color.r = 0.1f;
      color.g = 0.8f;
      color.b = 0.1f;
      break;
    default:  // grey
      color.r = color.g = color.b = 0.5f;
      break;
  }
  return color;
}

visualization_msgs::Marker toCubeList(const std::vector<rfm::CellClass>& cells,
                                      const rfm::CellBox& box, rfm::CellClass cell_class,
                                      double resolution, const std::string& frame,
                                      const ros::Time& stamp, const std::string& ns, int id) {
  visualization_msgs::Marker marker;
  marker.header.frame_id = frame;
  marker.header.stamp = stamp;
  marker.ns = ns;
  marker.id = id;
  marker.type = visualization_msgs::Marker::CUBE_LIST;
  marker.pose.orientation.w = 1.0;
  marker.scale.x = resolution;
  marker.scale.y = resolution;
  marker.scale.z = 0.1;
  marker.color = classColor(cell_class);
  if (!box.empty()) {
    const int width = box.width();
    for (size_t i = 0; i < cells.size(); ++i) {
      if (cells[i] != cell_class) continue;
      geometry_msgs::Point p;
      p.x = (box.min.x() + static_cast<int>(i % width) + 0.5) * resolution;
      p.y = (box.min.y() + static_cast<int>(i / width) + 0.5) * resolution;
      p.z = 0.05;
      marker.points.push_back(p);
    }
  }
  marker.action =
      marker.points.empty() ? visualization_msgs::Marker::DELETE : visualization_msgs::Marker::ADD;
  return marker;
}

visualization_msgs::Marker toCubeList(const rfm::GlobalMap2D& map, const rfm::CellBox& box,
                                      rfm::CellClass cell_class, double resolution,
                                      const std::string& frame, const ros::Time& stamp,
                                      const std::string& ns, int id) {
  std::vector<rfm::CellClass> cells;
  if (!box.empty()) map.extract(box, cells);
  return toCubeList(cells, box, cell_class, resolution, frame, stamp, ns, id);
}

}  // namespace rfm::ros_glue
