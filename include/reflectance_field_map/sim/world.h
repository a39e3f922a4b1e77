// 2D world geometry for the lidar simulator: line segments and circular arcs with a material,
// plus the moving circles (people) of the current instant. ROS-free.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace rfm::sim {

enum class Material : std::uint8_t { kDiffuse, kGlass, kMirror, kMetal };

const char* materialName(Material material);

// How a surface departs from an ideal one (the realistic physics reads it; see RealisticPhysics).
struct SurfaceFinish {
  double dirt = 0.0;  // probability that dirt scatters a beam back at normal incidence (any angle)
  double tilt = 0.0;  // out-of-plane lean of the surface's normal, rad (panes are not plumb)
};

// A person (or any moving diffuse disc) at the instant of a scan.
struct Circle {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0.25;
};

// Result of a ray query. `normal` is the unit surface normal facing the incoming ray.
struct Hit {
  double distance = std::numeric_limits<double>::infinity();
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  Material material = Material::kDiffuse;
  bool is_person = false;
  int surface_id = -1;  // index of the static surface, or -1 for a person
};

// Static surfaces of a scene. Walls are stored as primitives; glass and mirrors can be built with
// diffuse frame pieces at their ends and mullions in between (the widely visible sides of the
// paper's "H" feature).
class World {
 public:
  // Adds a single straight piece of one material.
  void addSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Material material,
                  const SurfaceFinish& finish = {});
  // Adds a circular arc (centre, radius, angles in radians, counter-clockwise from start to end).
  void addArc(const Eigen::Vector2d& center, double radius, double start_angle, double end_angle,
              Material material, const SurfaceFinish& finish = {});

  // Adds a wall of `material` from a to b. For non-diffuse walls, `frame_length` metres at each end
  // and a mullion of the same length every `mullion_spacing` metres (0 = none) are diffuse.
  void addFramedSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Material material,
                        double frame_length, double mullion_spacing,
                        const SurfaceFinish& finish = {});
  // Same for an arc; frame and mullion lengths are measured along the arc.
  void addFramedArc(const Eigen::Vector2d& center, double radius, double start_angle,
                    double end_angle, Material material, double frame_length,
                    double mullion_spacing, const SurfaceFinish& finish = {});

  // Nearest intersection of the ray origin + s * direction (direction unit length) with
  // s in (min_distance, max_distance], ignoring static surface `ignore_surface` (the one the ray
  // just left). People are tested too.
  std::optional<Hit> intersect(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                               double max_distance, const std::vector<Circle>& people,
                               int ignore_surface = -1, double min_distance = 1e-9) const;

  std::size_t segmentCount() const { return segments_.size(); }
  std::size_t arcCount() const { return arcs_.size(); }
  std::size_t surfaceCount() const { return segments_.size() + arcs_.size(); }

  // Axis-aligned bounds of all static surfaces (min, max); zero box if empty.
  std::pair<Eigen::Vector2d, Eigen::Vector2d> bounds() const;

  struct SegmentPrimitive {
    Eigen::Vector2d a, b;
    Material material;
    SurfaceFinish finish;
  };
  struct ArcPrimitive {
    Eigen::Vector2d center;
    double radius, start_angle, sweep;  // sweep > 0, counter-clockwise
    Material material;
    SurfaceFinish finish;
  };
  const std::vector<SegmentPrimitive>& segments() const { return segments_; }
  const std::vector<ArcPrimitive>& arcs() const { return arcs_; }
  // Finish of static surface `surface_id` (a Hit's surface_id; segments first, then arcs).
  const SurfaceFinish& finish(int surface_id) const;

 private:
  std::vector<SegmentPrimitive> segments_;
  std::vector<ArcPrimitive> arcs_;
};

}  // namespace rfm::sim
