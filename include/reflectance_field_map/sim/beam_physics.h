// Material reflectance models and the beam tracer: what a single lidar beam returns in a world of
// diffuse walls, glass, mirrors, shiny metal and people. ROS-free.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <vector>

#include "reflectance_field_map/sim/world.h"

namespace rfm::sim {

// Ground-truth class of one beam. Values equal the constants of msg/RayTruth.msg.
enum class BeamClass : std::uint8_t {
  kNoReturn = 0,
  kDiffuse = 1,
  kGlass = 2,
  kMetal = 3,
  kMotion = 4,
  kReflection = 5,
};

const char* beamClassName(BeamClass beam_class);

// How each material answers a beam. Angles are incidence angles from the surface normal.
struct MaterialModel {
  // Half-width of the window around the normal in which glass and mirrors return. It is drawn per
  // scan uniformly in [min, max] to mimic out-of-plane tilt from bumps and suspension loading.
  double specular_window_min_deg = 2.0;
  double specular_window_max_deg = 4.0;
  // Off-normal glass hits that are reflected specularly instead of transmitted (multipath).
  double glass_reflect_probability = 0.05;
  // Shiny metal returns within this lobe, and elsewhere with a small probability; otherwise it
  // behaves like a mirror.
  double metal_lobe_deg = 15.0;
  double metal_scatter_probability = 0.05;
  // Diffuse surfaces return up to this incidence angle (grazing); beyond it the beam is lost.
  double diffuse_max_incidence_deg = 89.0;
  // Maximum number of transmissions plus specular bounces before the beam is lost.
  int max_interactions = 4;

  // Throws std::invalid_argument naming the offending parameter.
  void validate() const;
};

// What the sensor measures for one beam before range noise and random dropouts.
struct BeamResult {
  double range = 0.0;  // folded path length; +inf when nothing returned
  BeamClass beam_class = BeamClass::kNoReturn;
  int interactions = 0;  // transmissions + specular bounces before the return
};

class BeamTracer {
 public:
  BeamTracer(const World& world, const MaterialModel& model) : world_(world), model_(model) {}

  // Traces one beam from `origin` along unit `direction`. `specular_window_rad` is the half-width
  // of the near-normal return window for glass and mirrors for this scan. Random draws (glass
  // multipath, metal scatter) use `rng`.
  BeamResult trace(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                   double range_max, const std::vector<Circle>& people, double specular_window_rad,
                   std::mt19937& rng) const;

  const MaterialModel& model() const { return model_; }

 private:
  const World& world_;
  MaterialModel model_;
};

}  // namespace rfm::sim
