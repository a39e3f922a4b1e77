#include "reflectance_field_map/core/reflection_removal.h"

#include "reflectance_field_map/core/detail/pass_through_detector.h"
#include "reflectance_field_map/core/detail/shared_leap.h"
#include "reflectance_field_map/core/ray_insertion.h"
#include "reflectance_field_map/core/ray_traversal.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

namespace rfm {
namespace {

using detail::besideGlassOrMetal;
using detail::PassThroughDetector;
using detail::SharedLeap;
using detail::staticCellLetsPass;

// Metres along a ray (unit `direction`) per cell along its major axis. No cell within Chebyshev
// distance c of a cell blocks: then neither does the ray's stretch of c of these from any point
// of that cell, which on a diagonal is 1.41 cells long.
double leapPerCell(const Eigen::Vector2d& direction, double resolution) {
  return resolution / direction.cwiseAbs().maxCoeff();
}

void undo(const BinUpdate& update, ReflectanceField& field) {
  if (update.hit) {
    field.revertHitAt(update.slot, update.bin);
  } else {
    field.revertMissAt(update.slot, update.bin);
  }
}

void redo(const BinUpdate& update, ReflectanceField& field) {
  if (update.hit) {
    field.applyHitAt(update.slot, update.bin);
  } else {
    field.applyMissAt(update.slot, update.bin);
  }
}

// Turns the field from `before` (one replay's updates) to `after` (the other's): updates only in
// `before` are undone, those only in `after` applied, and a slot whose bin took a hit in one and
// a miss in the other gets both. Both lists come from ScanInserter::collectUpdates: grouped by
// bin in ascending order, a slot at most once per bin. `marks` (one per window slot, all zero)
// pairs them bin by bin without sorting, and is left all zero.
void applyDifference(const std::vector<BinUpdate>& before, const std::vector<BinUpdate>& after,
                     std::vector<uint8_t>& marks, ReflectanceField& field) {
  constexpr uint8_t kMiss = 1, kHit = 2, kPaired = 3;
  size_t i = 0, j = 0;
  while (i < before.size() || j < after.size()) {
    const int bin = std::min(i < before.size() ? before[i].bin : INT16_MAX,
                             j < after.size() ? after[j].bin : INT16_MAX);
    size_t i_end = i, j_end = j;
    while (i_end < before.size() && before[i_end].bin == bin)
      ++i_end;
    while (j_end < after.size() && after[j_end].bin == bin)
      ++j_end;
    for (size_t k = i; k < i_end; ++k)
      marks[before[k].slot] = before[k].hit ? kHit : kMiss;
    for (size_t k = j; k < j_end; ++k) {
      uint8_t& mark = marks[after[k].slot];
      if (mark == 0) {
        redo(after[k], field);
      } else if ((mark == kHit) != after[k].hit) {
        undo({after[k].slot, after[k].bin, mark == kHit}, field);
        redo(after[k], field);
      }
      mark = kPaired;
    }
    for (size_t k = i; k < i_end; ++k) {
      uint8_t& mark = marks[before[k].slot];
      if (mark != kPaired) undo(before[k], field);
      mark = 0;
    }
    for (size_t k = j; k < j_end; ++k)
      marks[after[k].slot] = 0;
    i = i_end;
    j = j_end;
  }
}

}  // namespace

ReflectionRemover::ReflectionRemover(const ReflectionRemovalOptions& options,
                                     const ReflectanceField& field, const ActiveClasses& classes)
    : enabled_(options.reflection_removal_enabled),
      penetration_tolerance_(options.penetration_tolerance),
      buffer_size_(static_cast<size_t>(options.scan_buffer_size)),
      static_blocking_min_bins_(static_cast<int>(
          std::ceil(options.static_blocking_min_angle / field.geometry().binWidth() - 1e-9))),
      field_(field),
      classes_(classes) {}

void ReflectionRemover::passThroughDistances(const Ray* rays, size_t count,
                                             double* distances) const {
  const GridGeometry& geometry = field_.geometry();
  const double resolution = geometry.resolution();
  const ClearanceMap& clearance = classes_.clearance();
  // Most of a check is its first leaps over empty cells, and each leap waits for the clearance
  // lookup of the one before: rays leap side by side, so their lookups overlap. Neighbouring
  // beams first leap together (SharedLeap). Each ray then goes on alone from where its leaps
  // stopped, exactly as it would have on its own: leaps pass only cells that cannot block.
  constexpr int kTogether = 8;  // neighbouring rays sharing their first leaps
  constexpr int kSideBySide = 64;
  constexpr int kGroups = kSideBySide / kTogether;
  std::optional<PassThroughDetector> detectors[kSideBySide];
  double from[kSideBySide];       // m along each ray where its walk starts
  double leap_unit[kSideBySide];  // m per leap of one cell
  int leaping[kSideBySide];
  SharedLeap groups[kGroups];
  int leaping_groups[kGroups];
  for (size_t first = 0; first < count; first += kSideBySide) {
    const Ray* const block = rays + first;
    const int n = static_cast<int>(std::min<size_t>(kSideBySide, count - first));
    for (int i = 0; i < n; ++i) {
      const PassThroughDetector& detector =
          detectors[i].emplace(block[i], geometry, penetration_tolerance_);
      leap_unit[i] = leapPerCell(detector.direction(), resolution);
    }
    int active = 0;
    for (int g = 0; g * kTogether < n; ++g) {
      const int end = std::min(n, (g + 1) * kTogether);
      if (groups[g].start(block, detectors, g * kTogether, end)) leaping_groups[active++] = g;
    }
    while (active > 0) {
      int still_leaping = 0;
      for (int a = 0; a < active; ++a) {
        const int g = leaping_groups[a];
        if (groups[g].leap(clearance, geometry)) leaping_groups[still_leaping++] = g;
      }
      active = still_leaping;
    }
    // Cells within the tolerance of the end never decide: walks stop there.
    active = 0;
    for (int i = 0; i < n; ++i) {
      from[i] = groups[i / kTogether].reached();
      if (from[i] < detectors[i]->lastCandidate()) leaping[active++] = i;
    }
    while (active > 0) {
      int still_leaping = 0;
      for (int a = 0; a < active; ++a) {
        const int i = leaping[a];
        const PassThroughDetector& detector = *detectors[i];
        const Eigen::Vector2d at = block[i].origin + detector.direction() * from[i];
        const int clear = clearance.at(geometry.cellOf(at));
        if (clear < 2) continue;  // next to structure: the walk takes over
        from[i] += (clear - 1) * leap_unit[i];
        if (from[i] < detector.lastCandidate()) leaping[still_leaping++] = i;
      }
      active = still_leaping;
    }
    for (int i = 0; i < n; ++i) {
      PassThroughDetector& detector = *detectors[i];
      // Leaped past the last candidate (or none to check): nothing blocks, no walk to set up.
      distances[first + i] = from[i] < detector.lastCandidate()
                                 ? walkTowardsGlass(block[i], detector, from[i], leap_unit[i])
                                 : detector.distance();
    }
  }
}

double ReflectionRemover::walkTowardsGlass(const Ray& ray, PassThroughDetector& detector,
                                           double from, double leap_unit) const {
  const Eigen::Vector2d& direction = detector.direction();
  const double stop = detector.lastCandidate();
  const Eigen::Vector2d last = ray.origin + direction * stop;
  const GridGeometry& geometry = field_.geometry();
  const double resolution = geometry.resolution();
  const int bins = geometry.thetaBins();
  const ClearanceMap& clearance = classes_.clearance();
  auto class_of = [this](const CellIndex& cell) { return classes_.at(cell); };
  // Cells that cannot block (free, unknown, motion, unclassified) change nothing until the ray
  // is inside a blocking cell, so the walk leaps over them by the clearance and steps cell by
  // cell only near glass, metal and static structure. People's trails leave motion cells all
  // over an open space: leaping over those too is what keeps the check cheap there.
  while (from < stop) {
    if (!detector.blocked()) {
      const int clear = clearance.at(geometry.cellOf(ray.origin + direction * from));
      if (clear >= 2) {
        // No cell within clear - 1 of the current one blocks: nor does the ray's stretch.
        from += (clear - 1) * leap_unit;
        continue;
      }
    }
    double resume = stop;  // where the walk hands back to leaping, if it does
    walkWindowCells(
        ray.origin + direction * from, last, geometry.inverseResolution(), field_.window(), true,
        [&](int slot, int x, int y) {
          const CellClass c = classes_.atSlot(slot);
          // Asked only of static cells: whether they let the ray pass (staticCellLetsPass).
          auto reflective_near = [&](int bin) {
            const uint64_t* mask =
                frozen_.active() ? frozen_.maskOf({x, y}) : field_.reflectiveMaskAt(slot);
            return staticCellLetsPass(mask, field_.maskWords(), bin, bins,
                                      static_blocking_min_bins_, [&] {
                                        return besideGlassOrMetal({x, y}, class_of);
                                      });
          };
          if (!blocksRays(c)) {
            if (detector.blocked()) return detector.visit({x, y}, c, reflective_near, class_of);
            // Well clear of structure again: leap from here (the cell centre's projection lies
            // in this cell or a neighbour, none of them blocking).
            if (clearance.at({x, y}) >= 4) {
              const double along = (geometry.cellCenter({x, y}) - ray.origin).dot(direction);
              if (along > from + resolution) {
                resume = along;
                return false;
              }
            }
            return true;
          }
          return detector.visit({x, y}, c, reflective_near, class_of);
        });
    from = resume;
    if (detector.distance() >= 0.0 || resume >= stop) break;
  }
  return detector.distance();
}

size_t ReflectionRemover::cut(std::vector<Ray>& rays, std::vector<RayLabel>& labels,
                              ParallelRunner* runner) const {
  if (!checks()) return 0;
  // Read-only on the field and the classes: the rays split between threads freely.
  constexpr size_t kChunk = 64;
  parallelFor(runner, (rays.size() + kChunk - 1) / kChunk, 1, [&](size_t chunk, int) {
    const size_t first = chunk * kChunk, count = std::min(kChunk, rays.size() - first);
    double distances[kChunk];
    passThroughDistances(&rays[first], count, distances);
    for (size_t i = first; i < first + count; ++i) {
      const bool returned = rays[i].hit;  // only a return can be a reflection
      if (cutAtDistance(distances[i - first], rays[i]) && returned) {
        labels[rays[i].beam] = RayLabel::kReflection;
      }
    }
  });
  return std::count(labels.begin(), labels.end(), RayLabel::kReflection);
}

bool ReflectionRemover::cutAtDistance(double along, Ray& ray) const {
  if (along < 0.0) return false;
  // Evidence beyond the surface is discarded (Alg. 3): misses up to it, no hit. Even the misses
  // beyond glass are dropped: a mirror looks like glass in the field, and beyond a mirror the
  // path is folded, so its misses would erase real walls.
  const Eigen::Vector2d direction = (ray.end - ray.origin).normalized();
  ray.end = ray.origin + direction * (along + 0.5 * field_.geometry().resolution());
  ray.hit = false;
  return true;
}

void ReflectionRemover::freeze() {
  frozen_.freeze(field_, classes_);
}

void ReflectionRemover::keep(const std::vector<Ray>& rays, const Eigen::Vector2d& origin,
                             double first_beam_angle, double increment, double end_spread) {
  if (buffer_size_ == 0) return;
  buffer_.push_back({rays, origin, first_beam_angle, increment, end_spread});
  // A pending revert holds its scans, the oldest last (revertSome).
  while (buffer_.size() > buffer_size_ && revert_pending_ == 0)
    buffer_.pop_front();
}

void ReflectionRemover::startRevert(const CellBox& new_glass) {
  revert_box_ = new_glass;
  revert_pending_ = buffer_.size();
}

size_t ReflectionRemover::revertSome(size_t ray_budget, size_t min_scans, ScanInserter& inserter,
                                     ReflectanceField& field) {
  const size_t pending = revert_pending_;
  size_t spent = 0;
  while (revert_pending_ > 0 && (spent < ray_budget || pending - revert_pending_ < min_scans))
    spent += revertScan(buffer_[--revert_pending_], inserter, field);
  return pending - revert_pending_;
}

size_t ReflectionRemover::revertScan(KeptScan& kept, ScanInserter& inserter,
                                     ReflectanceField& field) {
  // Replay the scan's de-duplicated updates with and without the evidence beyond the glass and
  // apply the difference. De-duplication is per theta bin, so only the bins holding a changed
  // ray are replayed, and only rays crossing the new glass can change.
  const GridGeometry& geometry = field.geometry();
  const double resolution = geometry.resolution();
  RevertScratch& s = scratch_;
  auto by_beam = [](const Ray& ray, uint32_t beam) { return ray.beam < beam; };
  s.truncated.clear();
  size_t checked = 0;
  // Rays are in beam order: only those heading towards the new glass are looked at.
  beamsTowardsBox(revert_box_, resolution, kept.origin, kept.first_beam_angle, kept.increment,
                  kept.end_spread, s.beam_ranges);
  for (const BeamRange& range : s.beam_ranges) {
    auto it = std::lower_bound(kept.rays.begin(), kept.rays.end(), range.first, by_beam);
    for (; it != kept.rays.end() && it->beam <= range.last; ++it) {
      ++checked;
      Ray ray = *it;
      if (!clipRayToBox(revert_box_, resolution, ray)) continue;  // misses the new glass
      ray = *it;
      double distance = -1.0;
      passThroughDistances(&ray, 1, &distance);
      if (cutAtDistance(distance, ray)) s.truncated.emplace_back(it - kept.rays.begin(), ray);
    }
  }
  if (s.truncated.empty()) return checked;  // in beam order: the ranges ascend and are disjoint
  s.bin_changed.assign(geometry.thetaBins(), 0);
  for (const auto& changed : s.truncated)
    s.bin_changed[geometry.binOf(changed.second.angle)] = 1;
  s.old_rays.clear();
  s.new_rays.clear();
  auto next_truncated = s.truncated.begin();
  for (size_t k = 0; k < kept.rays.size(); ++k) {
    const bool cut = next_truncated != s.truncated.end() && next_truncated->first == k;
    const Ray& now = cut ? (next_truncated++)->second : kept.rays[k];
    if (!s.bin_changed[geometry.binOf(now.angle)]) continue;
    s.old_rays.push_back(kept.rays[k]);
    s.new_rays.push_back(now);
  }
  inserter.collectUpdates(s.old_rays, field, s.before);
  inserter.collectUpdates(s.new_rays, field, s.after);
  const size_t slots = static_cast<size_t>(field.window().sizeCells()) * field.window().sizeCells();
  if (s.slot_marks.size() != slots) s.slot_marks.assign(slots, 0);  // applyDifference clears them
  applyDifference(s.before, s.after, s.slot_marks, field);
  for (const auto& changed : s.truncated)
    kept.rays[changed.first] = changed.second;
  return checked + s.old_rays.size() + s.new_rays.size();
}

}  // namespace rfm
