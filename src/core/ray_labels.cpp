#include "reflectance_field_map/core/ray_labels.h"

#include "reflectance_field_map/core/ray_insertion.h"

#include <cmath>

namespace rfm {
namespace {

// A line within this many cells of a cell's centre may cross the cell.
constexpr double kHalfCellDiagonal = 0.7071067811865476;

// Whether the cell lies in the active region and its bin in the beam's direction, this return's
// hit included, is at most `limit`.
bool beamBinAtMost(const ReflectanceField& field, const Ray& beam, const CellIndex& cell,
                   int limit) {
  return field.inActiveRegion(cell) &&
         field.value(cell, field.geometry().binOf(beam.angle)) <= limit;
}

}  // namespace

bool arrivedInFreeCell(const ReflectanceField& field, const Ray& beam, const CellIndex& cell) {
  return beamBinAtMost(field, beam, cell, field.logOdds().hitStep() - 1);
}

bool arrivedInFirmlyFreeCell(const ReflectanceField& field, const Ray& beam,
                             const CellIndex& cell) {
  const LogOddsModel& log_odds = field.logOdds();
  return beamBinAtMost(field, beam, cell, log_odds.minValue() + log_odds.hitStep());
}

bool passesThroughCell(const Ray& ray, const CellIndex& cell, const GridGeometry& geometry) {
  const Eigen::Vector2d path = ray.end - ray.origin;
  const double length = path.norm();
  if (!(length > 0.0)) return false;
  const Eigen::Vector2d along = path / length;
  const Eigen::Vector2d to_centre = geometry.cellCenter(cell) - ray.origin;
  const double distance = to_centre.dot(along);
  const double lateral = std::abs(to_centre.x() * along.y() - to_centre.y() * along.x());
  return distance > 0.0 && distance < length - geometry.resolution() &&
         lateral <= kHalfCellDiagonal * geometry.resolution();
}

std::vector<RayLabel> labelRays(const std::vector<Ray>& rays, size_t beams,
                                const ReflectionRemover& reflections, const ActiveClasses& classes,
                                const CellBox& window_box, const GridGeometry& geometry,
                                double evidence_range, bool final_map,
                                const std::vector<uint8_t>* checked_beams,
                                const ReflectanceField* inserted, ArrivalMarks* arrivals) {
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
  // An arrival also needs the scan's neighbouring beams to have stopped short of the cell: a pane
  // at the edge of its return cone lets the next beam through, a person blocks it.
  size_t index = 0;
  // Rays skip invalid beams: the ray beside is the neighbouring beam only when their beams are.
  auto beside_passes = [&](size_t other, const CellIndex& cell) {
    const uint32_t a = rays[index].beam, b = rays[other].beam;
    return (a == b + 1 || b == a + 1) && passesThroughCell(rays[other], cell, geometry);
  };
  auto arrived = [&](const CellIndex& cell) {
    if (!inserted) return false;
    if (arrivals && arrivals->nearMarked(cell)) return true;
    if (!arrivedInFreeCell(*inserted, rays[index], cell)) return false;
    if (index > 0 && beside_passes(index - 1, cell)) return false;
    if (index + 1 < rays.size() && beside_passes(index + 1, cell)) return false;
    if (arrivals && arrivedInFirmlyFreeCell(*inserted, rays[index], cell)) arrivals->mark(cell);
    return true;
  };
  size_t next_checked = 0;
  for (; index < rays.size(); ++index) {
    const Ray& ray = rays[index];
    if (!ray.hit) continue;  // no return: nothing to keep or remove
    if (next_checked < checked.size() && checked[next_checked].beam == ray.beam &&
        through[next_checked++] >= 0.0) {
      labels[ray.beam] = RayLabel::kReflection;
      continue;
    }
    labels[ray.beam] = labelEndpoint(ray, geometry, evidence_range, final_map, class_of, arrived);
  }
  return labels;
}

}  // namespace rfm
