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

// The physics of procedural scenes (a scene's `physics` section; off otherwise, and then
// MaterialModel alone applies, with today's random draws). Angles in degrees, as in the scene file.
// Glass, mirrors and metal return when the angle between the beam and their normal, in 3D, is
// within a cone: the in-plane incidence and the out-of-plane angle between the beam (tilted with
// the chassis and its mount) and the surface's normal (tilted by SurfaceFinish::tilt) add in
// quadrature.
struct RealisticPhysics {
  bool enabled = false;
  // Glass and mirrors: half-angle of the return cone around the normal.
  double return_cone_deg = 2.5;
  // Chassis pitch and roll from floor bumps while driving: standard deviation at full speed
  // (0.5 m/s and faster), correlation time of the bumps, and the tilt left when standing still.
  double bump_tilt_deg = 0.5;
  double bump_correlation_s = 0.15;
  double standing_tilt_deg = 0.05;
  // Glass reflects a share of off-cone beams specularly: the Fresnel reflectance of a pane (two
  // faces) of this refractive index, about 8 % near the normal and most of the light at grazing.
  double refractive_index = 1.52;
  // Glass with nothing detectable behind it returns a weak echo of its own with probability
  // empty_echo_probability * exp(-incidence / empty_echo_decay_deg).
  double empty_echo_probability = 0.2;
  double empty_echo_decay_deg = 20.0;
  // Shiny metal returns within its lobe, and beyond it with probability
  // metal_tail_probability * exp(-(angle - lobe) / metal_tail_decay_deg); otherwise it mirrors.
  double metal_lobe_deg = 12.0;
  double metal_tail_probability = 0.1;
  double metal_tail_decay_deg = 10.0;
  // Diffuse surfaces return up to this incidence; a returned beam is lost with probability
  // grazing_dropout * (incidence / diffuse_max_incidence_deg)^6 (faint spot at grazing) plus
  // range_dropout * (range / range_max)^2 (dark surfaces fade before the sensor's range), and a
  // beam past the limit bounces specularly with probability gloss_probability (glossy paint).
  double diffuse_max_incidence_deg = 86.0;
  double grazing_dropout = 0.2;
  double range_dropout = 0.1;
  double gloss_probability = 0.1;
  int max_interactions = 4;

  // Throws std::invalid_argument naming the offending parameter.
  void validate() const;
};

// Unpolarised Fresnel reflectance of a glass pane (two faces, incoherent) at `incidence` (rad).
double paneReflectance(double incidence, double refractive_index);

// What the sensor measures for one beam before range noise and random dropouts.
struct BeamResult {
  double range = 0.0;  // folded path length; +inf when nothing returned
  BeamClass beam_class = BeamClass::kNoReturn;
  int interactions = 0;  // transmissions + specular bounces before the return
};

class BeamTracer {
 public:
  BeamTracer(const World& world, const MaterialModel& model, const RealisticPhysics& physics = {})
      : world_(world), model_(model), physics_(physics) {}

  // Traces one beam from `origin` along unit `direction`. `specular_window_rad` is the half-width
  // of the near-normal return window for glass and mirrors for this scan. Random draws (glass
  // multipath, metal scatter) use `rng`.
  BeamResult trace(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                   double range_max, const std::vector<Circle>& people, double specular_window_rad,
                   std::mt19937& rng) const;

  // Traces one beam with the RealisticPhysics. `elevation` is the beam's out-of-plane angle (rad)
  // from the chassis tilt and the sensor mount.
  BeamResult traceRealistic(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                            double range_max, const std::vector<Circle>& people, double elevation,
                            std::mt19937& rng) const;

  const MaterialModel& model() const { return model_; }
  const RealisticPhysics& physics() const { return physics_; }

 private:
  const World& world_;
  MaterialModel model_;
  RealisticPhysics physics_;
};

}  // namespace rfm::sim
