#include "reflectance_field_map/sim/beam_physics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "require_range.h"

namespace rfm::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

using detail::requireRange;

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

void RealisticPhysics::validate() const {
  requireRange(return_cone_deg, 0.0, 45.0, "return_cone_deg");
  requireRange(bump_tilt_deg, 0.0, 10.0, "bump_tilt_deg");
  requireRange(bump_correlation_s, 0.001, 10.0, "bump_correlation_s");
  requireRange(standing_tilt_deg, 0.0, 10.0, "standing_tilt_deg");
  requireRange(refractive_index, 1.0, 3.0, "refractive_index");
  requireRange(empty_echo_probability, 0.0, 1.0, "empty_echo_probability");
  requireRange(empty_echo_decay_deg, 0.1, 90.0, "empty_echo_decay_deg");
  requireRange(metal_lobe_deg, 0.0, 90.0, "metal_lobe_deg");
  requireRange(metal_tail_probability, 0.0, 1.0, "metal_tail_probability");
  requireRange(metal_tail_decay_deg, 0.1, 90.0, "metal_tail_decay_deg");
  requireRange(diffuse_max_incidence_deg, 0.0, 90.0, "diffuse_max_incidence_deg");
  requireRange(grazing_dropout, 0.0, 1.0, "grazing_dropout");
  requireRange(range_dropout, 0.0, 1.0, "range_dropout");
  requireRange(gloss_probability, 0.0, 1.0, "gloss_probability");
  requireRange(max_interactions, 0, 32, "max_interactions");
}

double paneReflectance(double incidence, double refractive_index) {
  const double cos_i = std::cos(incidence);
  const double sin_t = std::sin(incidence) / refractive_index;
  const double cos_t = std::sqrt(std::max(0.0, 1.0 - sin_t * sin_t));
  const double n = refractive_index;
  const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
  const double rp = (cos_t - n * cos_i) / (cos_t + n * cos_i);
  const double face = 0.5 * (rs * rs + rp * rp);
  // Light bounces between the two faces; summed incoherently the pane reflects 2R / (1 + R).
  return 2.0 * face / (1.0 + face);
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

BeamResult BeamTracer::traceRealistic(const Eigen::Vector2d& origin,
                                      const Eigen::Vector2d& direction, double range_max,
                                      const std::vector<Circle>& people, double elevation,
                                      std::mt19937& rng) const {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const RealisticPhysics& p = physics_;
  const double cone = p.return_cone_deg * kDegToRad;
  const double lobe = p.metal_lobe_deg * kDegToRad;
  const double diffuse_max = p.diffuse_max_incidence_deg * kDegToRad;

  BeamResult result;
  Eigen::Vector2d position = origin;
  Eigen::Vector2d heading = direction;
  double travelled = 0.0;
  int last_surface = -1;
  // The first pane the beam crossed head-on, for the weak echo of glass with nothing behind it.
  double pane_distance = -1.0, pane_incidence = 0.0;

  auto finish = [&](BeamClass direct_class, double distance) {
    result.range = travelled + distance;
    result.beam_class = result.interactions > 0 ? BeamClass::kReflection : direct_class;
    return result;
  };
  // Nothing came back: the pane's own weak echo is all the sensor receives, if it is strong enough.
  auto lost = [&]() {
    if (pane_distance > 0.0 &&
        uniform(rng) < p.empty_echo_probability *
                           std::exp(-pane_incidence / (p.empty_echo_decay_deg * kDegToRad))) {
      result.range = pane_distance;
      result.beam_class = BeamClass::kGlass;
      result.interactions = 0;
      return result;
    }
    result.range = std::numeric_limits<double>::infinity();
    result.beam_class = BeamClass::kNoReturn;
    return result;
  };

  while (true) {
    const std::optional<Hit> hit =
        world_.intersect(position, heading, range_max - travelled, people, last_surface);
    if (!hit) return lost();
    const double incidence = std::acos(std::min(1.0, std::abs(hit->normal.dot(heading))));

    if (hit->is_person || hit->material == Material::kDiffuse) {
      const BeamClass direct = hit->is_person ? BeamClass::kMotion : BeamClass::kDiffuse;
      if (incidence <= diffuse_max) {
        const double share = incidence / std::max(diffuse_max, 1e-9);
        const double reach = (travelled + hit->distance) / range_max;
        const double grazing = share * share * share;
        if (uniform(rng) <
            p.grazing_dropout * grazing * grazing + p.range_dropout * reach * reach) {
          return lost();
        }
        return finish(direct, hit->distance);
      }
      if (hit->is_person || uniform(rng) >= p.gloss_probability) return lost();
    } else {
      const SurfaceFinish& surface = world_.finish(hit->surface_id);
      const double out_of_plane = elevation - surface.tilt;
      const double off_normal = std::hypot(incidence, out_of_plane);
      // Dirt scatters like a faint diffuse surface, at any angle.
      const bool dirt_scatter = uniform(rng) < surface.dirt * std::cos(incidence);
      switch (hit->material) {
        case Material::kGlass:
          if (off_normal <= cone || dirt_scatter) return finish(BeamClass::kGlass, hit->distance);
          if (uniform(rng) >= paneReflectance(incidence, p.refractive_index)) {
            if (result.interactions == 0 && pane_distance < 0.0) {
              pane_distance = hit->distance;
              pane_incidence = incidence;
            }
            // Transmitted: the heading stays.
            if (result.interactions >= p.max_interactions) return lost();
            ++result.interactions;
            travelled += hit->distance;
            position = hit->point;
            last_surface = hit->surface_id;
            continue;
          }
          break;
        case Material::kMirror:
          if (off_normal <= cone || dirt_scatter) return finish(BeamClass::kMetal, hit->distance);
          break;
        case Material::kMetal:
          if (off_normal <= lobe || dirt_scatter ||
              uniform(rng) <
                  p.metal_tail_probability *
                      std::exp(-(off_normal - lobe) / (p.metal_tail_decay_deg * kDegToRad))) {
            return finish(BeamClass::kMetal, hit->distance);
          }
          break;
        case Material::kDiffuse:
          break;
      }
    }
    // Specular bounce.
    if (result.interactions >= p.max_interactions) return lost();
    ++result.interactions;
    travelled += hit->distance;
    position = hit->point;
    heading = heading - 2.0 * heading.dot(hit->normal) * hit->normal;
    last_surface = hit->surface_id;
  }
}

}  // namespace rfm::sim
