#include "reflectance_field_map/sim/beam_physics.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rfm::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

void requireRange(double value, double low, double high, const char* name) {
  if (!(value >= low && value <= high)) {
    throw std::invalid_argument(std::string(name) + " must be in [" + std::to_string(low) + ", " +
                                std::to_string(high) + "], got " + std::to_string(value));
  }
}

}  // namespace

const char* beamClassName(BeamClass beam_class) {
  switch (beam_class) {
    case BeamClass::kNoReturn:
      return "no_return";
    case BeamClass::kDiffuse:
      return "diffuse";
    case BeamClass::kGlass:
      return "glass";
    case BeamClass::kMetal:
      return "metal";
    case BeamClass::kMotion:
      return "motion";
    case BeamClass::kReflection:
      return "reflection";
  }
  return "unknown";
}

void MaterialModel::validate() const {
  requireRange(specular_window_min_deg, 0.0, 45.0, "specular_window_min_deg");
  requireRange(specular_window_max_deg, specular_window_min_deg, 45.0, "specular_window_max_deg");
  requireRange(glass_reflect_probability, 0.0, 1.0, "glass_reflect_probability");
  requireRange(metal_lobe_deg, 0.0, 90.0, "metal_lobe_deg");
  requireRange(metal_scatter_probability, 0.0, 1.0, "metal_scatter_probability");
  requireRange(diffuse_max_incidence_deg, 0.0, 90.0, "diffuse_max_incidence_deg");
  requireRange(max_interactions, 0, 32, "max_interactions");
}

BeamResult BeamTracer::trace(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                             double range_max, const std::vector<Circle>& people,
                             double specular_window_rad, std::mt19937& rng) const {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double cos_specular_window = std::cos(specular_window_rad);
  const double cos_metal_lobe = std::cos(model_.metal_lobe_deg * kDegToRad);
  const double cos_diffuse_max = std::cos(model_.diffuse_max_incidence_deg * kDegToRad);

  BeamResult result;
  Eigen::Vector2d position = origin;
  Eigen::Vector2d heading = direction;
  double travelled = 0.0;
  int last_surface = -1;

  // Every return after a transmission or a specular bounce is a reflection: its range is not the
  // distance to a surface along the beam.
  auto finish = [&](BeamClass direct_class, double distance) {
    result.range = travelled + distance;
    result.beam_class = result.interactions > 0 ? BeamClass::kReflection : direct_class;
    return result;
  };

  while (true) {
    const std::optional<Hit> hit =
        world_.intersect(position, heading, range_max - travelled, people, last_surface);
    if (!hit) break;  // nothing within the remaining range: no echo
    const double cos_incidence = std::abs(hit->normal.dot(heading));

    if (hit->is_person) return finish(BeamClass::kMotion, hit->distance);

    bool continue_specular = false;
    bool transmit = false;
    switch (hit->material) {
      case Material::kDiffuse:
        if (cos_incidence >= cos_diffuse_max) return finish(BeamClass::kDiffuse, hit->distance);
        break;  // beyond grazing: the spot is too faint to detect
      case Material::kGlass:
        if (cos_incidence >= cos_specular_window) return finish(BeamClass::kGlass, hit->distance);
        if (uniform(rng) < model_.glass_reflect_probability) {
          continue_specular = true;
        } else {
          transmit = true;
        }
        break;
      case Material::kMirror:
        if (cos_incidence >= cos_specular_window) return finish(BeamClass::kMetal, hit->distance);
        continue_specular = true;
        break;
      case Material::kMetal:
        if (cos_incidence >= cos_metal_lobe) return finish(BeamClass::kMetal, hit->distance);
        if (uniform(rng) < model_.metal_scatter_probability) {
          return finish(BeamClass::kMetal, hit->distance);
        }
        continue_specular = true;
        break;
    }
    if (!continue_specular && !transmit) break;
    if (result.interactions >= model_.max_interactions) break;

    ++result.interactions;
    travelled += hit->distance;
    position = hit->point;
    if (continue_specular) heading = heading - 2.0 * heading.dot(hit->normal) * hit->normal;
    last_surface = hit->surface_id;
  }
  result.range = std::numeric_limits<double>::infinity();
  result.beam_class = BeamClass::kNoReturn;
  return result;
}

}  // namespace rfm::sim
