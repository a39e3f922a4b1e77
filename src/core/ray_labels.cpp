#include "reflectance_field_map/core/ray_labels.h"

#include "reflectance_field_map/core/ray_insertion.h"

namespace rfm {

bool arrivedInFreeCell(const ReflectanceField& field, const Ray& beam, const CellIndex& cell) {
  if (!field.inActiveRegion(cell)) return false;
  return field.value(cell, field.geometry().binOf(beam.angle)) < field.logOdds().hitStep();
}

std::vector<RayLabel> labelRays(const std::vector<Ray>& rays, size_t beams,
                                const ReflectionRemover& reflections, const ActiveClasses& classes,
                                const CellBox& window_box, const GridGeometry& geometry,
                                double evidence_range, bool final_map,
                                const std::vector<uint8_t>* checked_beams,
                                const ReflectanceField* inserted) {
  std::vector<RayLabel> labels(beams, RayLabel::kNoReturn);
  // The reflection check of every hit ray first, side by side (passThroughDistances).
  std::vector<Ray> checked;
  std::vector<double> through;
  if (reflections.checks()) {
    checked.reserve(rays.size());  // grown one by one, it reallocated ten times a scan
    for (const Ray& ray : rays) {
      if (checked_beams && ray.beam < checked_beams->size() && (*checked_beams)[ray.beam]) continue;
      Ray inside = ray;
      if (ray.hit && clipRayToBox(window_box, geometry.resolution(), inside)) {
        checked.push_back(inside);
      }
    }
    through.resize(checked.size());
    reflections.passThroughDistances(checked.data(), checked.size(), through.data());
  }
  auto class_of = [&classes](const CellIndex& cell) { return classes.at(cell); };
  const Ray* current = nullptr;
  auto arrived = [&inserted, &current](const CellIndex& cell) {
    return inserted && arrivedInFreeCell(*inserted, *current, cell);
  };
  size_t next_checked = 0;
  for (const Ray& ray : rays) {
    if (!ray.hit) continue;  // no return: nothing to keep or remove
    if (next_checked < checked.size() && checked[next_checked].beam == ray.beam &&
        through[next_checked++] >= 0.0) {
      labels[ray.beam] = RayLabel::kReflection;
      continue;
    }
    current = &ray;
    labels[ray.beam] = labelEndpoint(ray, geometry, evidence_range, final_map, class_of, arrived);
  }
  return labels;
}

}  // namespace rfm
