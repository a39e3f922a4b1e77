#include "reflectance_field_map/tools/transient_evidence.h"

#include "reflectance_field_map/core/ray_traversal.h"

#include <cmath>
#include <cstdio>

namespace rfm::tools {

TransientEvidence::TransientEvidence(double resolution, int min_x, int min_y, int width, int height,
                                     int margin_cells)
    : resolution_(resolution),
      min_x_(min_x),
      min_y_(min_y),
      width_(width),
      height_(height),
      margin_cells_(margin_cells),
      hits_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0),
      passes_(hits_.size(), 0),
      last_hit_scan_(hits_.size(), 0),
      last_pass_scan_(hits_.size(), 0) {}

void TransientEvidence::addScan(const TimedScan& timed) {
  const uint32_t scan = ++scans_;
  const LaserScan2D& s = timed.scan;
  const Pose2D& pose = timed.sensor_pose;
  const double inverse_resolution = 1.0 / resolution_;
  // Only returns show where a beam went: a beam without one may have dropped out (a far or
  // dark wall) as well as met nothing.
  std::vector<Eigen::Vector2d> ends;
  ends.reserve(s.ranges.size());
  for (std::size_t beam = 0; beam < s.ranges.size(); ++beam) {
    if (classifyBeam(s.ranges[beam], s.range_min, s.range_max) != BeamReading::kReturn) continue;
    const double angle = pose.yaw + s.angle_min + static_cast<double>(beam) * s.angle_increment;
    ends.push_back(pose.position + static_cast<double>(s.ranges[beam]) *
                                       Eigen::Vector2d(std::cos(angle), std::sin(angle)));
  }
  // Hits first, so a cell one beam ends in and another crosses counts as hit.
  for (const Eigen::Vector2d& end : ends) {
    const int x = floorToInt(end.x() * inverse_resolution);
    const int y = floorToInt(end.y() * inverse_resolution);
    if (!inBox(x, y)) continue;
    const std::size_t i = index(x, y);
    if (last_hit_scan_[i] != scan) {
      last_hit_scan_[i] = scan;
      ++hits_[i];
    }
  }
  for (const Eigen::Vector2d& end : ends) {
    GridRayTraversal ray(pose.position, end, inverse_resolution);
    for (; ray.remaining() > margin_cells_; ray.next()) {  // cells well before the end cell
      const CellIndex& cell = ray.cell();
      if (!inBox(cell.x(), cell.y())) continue;
      const std::size_t i = index(cell.x(), cell.y());
      if (last_hit_scan_[i] == scan || last_pass_scan_[i] == scan) continue;
      last_pass_scan_[i] = scan;
      ++passes_[i];
    }
  }
}

uint32_t TransientEvidence::hitScans(int x, int y) const {
  return inBox(x, y) ? hits_[index(x, y)] : 0;
}

uint32_t TransientEvidence::passedScans(int x, int y) const {
  return inBox(x, y) ? passes_[index(x, y)] : 0;
}

void mapCellOrigin(const GridMap& map, int& cell_x, int& cell_y) {
  const double x = map.origin_x / map.resolution, y = map.origin_y / map.resolution;
  if (std::abs(x - std::round(x)) > 1e-3 || std::abs(y - std::round(y)) > 1e-3) {
    char text[128];
    std::snprintf(text, sizeof(text), "the map's origin (%.6f, %.6f) is not on its grid's cells",
                  map.origin_x, map.origin_y);
    throw MapFileError(text);
  }
  cell_x = static_cast<int>(std::round(x));
  cell_y = static_cast<int>(std::round(y));
}

PeopleLeft measurePeopleLeft(const GridMap& map, const TransientEvidence& evidence) {
  if (std::abs(map.resolution - evidence.resolution()) > 1e-9 * map.resolution) {
    throw MapFileError("the map's resolution differs from the evidence's");
  }
  int ox = 0, oy = 0;
  mapCellOrigin(map, ox, oy);
  PeopleLeft result;
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      if (map.occupancyAt(x, y) != Occupancy::kOccupied) continue;
      ++result.occupied;
      result.transient += evidence.isTransient(ox + x, oy + y);
    }
  }
  return result;
}

}  // namespace rfm::tools
