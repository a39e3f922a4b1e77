#pragma once

// A tiny ray caster for core tests: diffuse walls, glass that returns only near its normal,
// mirrors that fold the ray, and round pedestrians. The full simulator lives in src/sim.

#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/mapper.h"

#include <cmath>
#include <limits>
#include <vector>

namespace rfm {
namespace testing {

enum class Material { kDiffuse, kGlass, kMirror };

struct Segment {
  Eigen::Vector2d a, b;
  Material material = Material::kDiffuse;
};

struct Disc {
  Eigen::Vector2d centre;
  double radius = 0.25;
};

class SyntheticWorld {
 public:
  std::vector<Segment> segments;
  std::vector<Disc> people;
  double glass_window = 3.0 * kPi / 180.0;  // returns within this of the normal

  // A glass pane from a to b with short diffuse frames at both ends.
  void addFramedPane(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double frame = 0.06) {
    const Eigen::Vector2d u = (b - a).normalized();
    segments.push_back({a, a + frame * u, Material::kDiffuse});
    segments.push_back({a + frame * u, b - frame * u, Material::kGlass});
    segments.push_back({b - frame * u, b, Material::kDiffuse});
  }
  void addWall(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    segments.push_back({a, b, Material::kDiffuse});
  }

  // Range along the ray, or +inf when nothing returns within max_range.
  double cast(Eigen::Vector2d origin, Eigen::Vector2d direction, double max_range) const {
    double travelled = 0.0;
    for (int bounce = 0; bounce < 4; ++bounce) {
      double best = std::numeric_limits<double>::infinity();
      const Segment* hit_segment = nullptr;
      for (const Segment& s : segments) {
        const double t = intersect(origin, direction, s);
        if (t > 1e-9 && t < best) {
          best = t;
          hit_segment = &s;
        }
      }
      bool person = false;
      for (const Disc& d : people) {
        const double t = intersectDisc(origin, direction, d);
        if (t > 1e-9 && t < best) {
          best = t;
          person = true;
        }
      }
      if (!std::isfinite(best) || travelled + best >= max_range) break;
      if (person || hit_segment->material == Material::kDiffuse) return travelled + best;
      const Eigen::Vector2d tangent = (hit_segment->b - hit_segment->a).normalized();
      const Eigen::Vector2d normal(-tangent.y(), tangent.x());
      const double incidence = std::acos(std::min(1.0, std::abs(direction.dot(normal))));
      if (incidence < glass_window) return travelled + best;
      travelled += best;
      origin += best * direction;
      if (hit_segment->material == Material::kMirror) {
        direction = direction - 2.0 * direction.dot(normal) * normal;
      }
      origin += 1e-6 * direction;
    }
    return std::numeric_limits<double>::infinity();
  }

  // A UTM-30LX-like scan: 1081 beams over 270 deg.
  LaserScan2D scan(const Pose2D& sensor, int beams = 1081, double fov = 1.5 * kPi,
                   double max_range = 30.0) const {
    LaserScan2D out;
    out.angle_min = static_cast<float>(-fov / 2);
    out.angle_increment = static_cast<float>(fov / (beams - 1));
    out.angle_max = static_cast<float>(out.angle_min + (beams - 1) * out.angle_increment);
    out.range_min = 0.1f;
    out.range_max = static_cast<float>(max_range);
    out.ranges.resize(beams);
    for (int i = 0; i < beams; ++i) {
      const double angle =
          sensor.yaw + out.angle_min + i * static_cast<double>(out.angle_increment);
      out.ranges[i] = static_cast<float>(
          cast(sensor.position, Eigen::Vector2d(std::cos(angle), std::sin(angle)), max_range));
    }
    return out;
  }

  TimedScan timedScan(const Pose2D& robot, double stamp = 0.0) const {
    TimedScan t;
    t.stamp = stamp;
    t.robot_pose = robot;
    t.sensor_pose = robot;
    t.scan = scan(robot);
    return t;
  }

 private:
  static double intersect(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Segment& s) {
    const Eigen::Vector2d e = s.b - s.a;
    const double denom = d.x() * e.y() - d.y() * e.x();
    if (std::abs(denom) < 1e-12) return -1.0;
    const Eigen::Vector2d w = s.a - o;
    const double t = (w.x() * e.y() - w.y() * e.x()) / denom;
    const double u = (w.x() * d.y() - w.y() * d.x()) / denom;
    return (u >= 0.0 && u <= 1.0) ? t : -1.0;
  }
  static double intersectDisc(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Disc& c) {
    const Eigen::Vector2d m = o - c.centre;
    const double b = m.dot(d), cc = m.squaredNorm() - c.radius * c.radius;
    const double disc = b * b - cc;
    if (disc < 0.0) return -1.0;
    return -b - std::sqrt(disc);
  }
};

// Poses along a straight line, heading `yaw`.
inline std::vector<Pose2D> straightPath(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                        int steps, double yaw) {
  std::vector<Pose2D> poses;
  for (int i = 0; i < steps; ++i) {
    const double s = steps == 1 ? 0.0 : static_cast<double>(i) / (steps - 1);
    poses.push_back({from + s * (to - from), yaw});
  }
  return poses;
}

}  // namespace testing
}  // namespace rfm
