// The reflection check of Alg. 3 for one ray, fed the cells along it (ReflectionRemover).
#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdlib>
#include <optional>

namespace rfm::detail {

// Whether a glass or metal cell touches `cell` (8-neighbourhood).
template <typename ClassOf>
bool besideGlassOrMetal(const CellIndex& cell, ClassOf&& class_of) {
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (isGlassOrMetal(class_of(CellIndex(cell.x() + dx, cell.y() + dy)))) return true;
    }
  }
  return false;
}

// Whether a static cell with reflective `mask` (`words` words, null: reflective nowhere) lets a
// returned ray of theta bin `bin` pass: where the directions it reflects in are too few to tell
// (under `min_bins`), and where it reflects in the ray's direction or next to it (a wall grazed
// at a shallow angle is hit in neighbouring directions). Beside glass or metal
// (beside_glass_or_metal(), asked last: a pane's end drawn static, its frame) only the ray's own
// direction counts: the neighbouring ones are where the pane's reflections pass.
template <typename BesideGlassOrMetal>
bool staticCellLetsPass(const uint64_t* mask, int words, int bin, int bins, int min_bins,
                        BesideGlassOrMetal&& beside_glass_or_metal) {
  if (!mask) return false;
  if (maskBit(mask, bin) || countMaskBits(mask, words) < min_bins) return true;
  return reflectiveNear(mask, bin, bins) && !beside_glass_or_metal();
}

// Whether the obstacle neighbours of `cell` (8-neighbourhood) all lie within 90 deg of their mean
// direction, on one side of it: the end of a structure (a door jamb, a room's corner, the flank of
// a pillar), not a cell inside a surface, which has obstacles on opposite sides.
template <typename ClassOf>
bool endsAStructure(const CellIndex& cell, ClassOf&& class_of) {
  int offsets[8][2];
  int count = 0, sum_x = 0, sum_y = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if ((dx == 0 && dy == 0) || !isObstacle(class_of(CellIndex(cell.x() + dx, cell.y() + dy)))) {
        continue;
      }
      offsets[count][0] = dx;
      offsets[count][1] = dy;
      ++count;
      sum_x += dx;
      sum_y += dy;
    }
  }
  for (int i = 0; i < count; ++i) {
    if (offsets[i][0] * sum_x + offsets[i][1] * sum_y <= 0) return false;
  }
  return count > 0;
}

// Reflection check of Alg. 3, fed cell by cell along a ray: finds the first blocking cell the
// ray passes through. A blocking cell is glass or metal, or static and not reflective in the
// ray's direction (reflective_near: staticCellLetsPass), that the ray passes through near its
// centre (not a clipped corner). For a ray without a return every static cell blocks: structure
// that reflects in its direction would have returned it (a dropout), so nothing beyond was
// observed. Nor does a static cell block a return on static structure where the ray entered its
// structure at a cell that ends it: a cell is wider than a surface, and a ray through a doorway
// or past a pillar crosses the jamb's or the flank's cell beside the structure in it, and then,
// passing at a shallow angle, the next cells of a wall drawn two cells thick. Its return agrees
// with the map. Passing through means crossing it: the ray comes out into a non-obstacle cell more
// than `penetration_tolerance` before its end. A ray grazing along a wall stays inside the wall's
// cells up to its end, and a ray ending on a surface ends within the tolerance: neither counts.
class PassThroughDetector {
 public:
  PassThroughDetector(const Ray& ray, const GridGeometry& geometry, double penetration_tolerance)
      : geometry_(geometry),
        origin_(ray.origin),
        end_(ray.end),
        angle_(ray.angle),
        returned_(ray.hit) {
    const Eigen::Vector2d delta = ray.end - ray.origin;
    const double length = delta.norm();
    direction_ = length > 0.0 ? Eigen::Vector2d(delta / length) : Eigen::Vector2d(1.0, 0.0);
    last_candidate_ = length - penetration_tolerance;
    if (last_candidate_ < 0.0) decided_ = true;
  }

  // Feeds the next cell; false once decided (stop walking). reflective_near(bin) is asked only
  // for static cells, class_of(cell) only for the neighbours of a candidate.
  template <typename ReflectiveNear, typename ClassOf>
  bool visit(const CellIndex& cell, CellClass c, ReflectiveNear&& reflective_near,
             ClassOf&& class_of) {
    if (decided_) return false;
    const double along = (geometry_.cellCenter(cell) - origin_).dot(direction_);
    if (along > last_candidate_) {
      decided_ = true;
      blocked_at_ = -1.0;
      return false;
    }
    if (blocked_at_ < 0.0) {
      // A structure's cells come one after another; a cell not touching the last one enters a
      // structure anew. Only a return can pass a structure's end (passesAStructureEnd).
      if (returned_ && blocksRays(c)) {
        if (!(run_start_ && std::abs(cell.x() - last_visited_.x()) <= 1 &&
              std::abs(cell.y() - last_visited_.y()) <= 1)) {
          run_start_ = cell;
          run_enters_at_end_ = -1;
        }
        last_visited_ = cell;
      }
      const bool blocking =
          c == CellClass::kGlass || c == CellClass::kMetal ||
          (c == CellClass::kStatic &&
           (!returned_ || (!reflective_near(bin()) && !passesAStructureEnd(class_of))));
      if (blocking && passesNearCentre(cell) && crossesASurface(cell, class_of)) {
        blocked_at_ = along;
      }
    } else if (!isObstacle(c)) {
      decided_ = true;  // came out on the other side
      return false;
    }
    return true;
  }

  bool blocked() const { return blocked_at_ >= 0.0; }
  // The ray's unit direction, and the distance along it beyond which no cell decides (the
  // penetration tolerance before its end): where a walk feeding visit() may stop.
  const Eigen::Vector2d& direction() const { return direction_; }
  double lastCandidate() const { return last_candidate_; }

  // Distance (m, along the ray) of the blocking cell passed through, or negative. Complete once
  // the walk reached the ray's end or visit() returned false.
  double distance() const { return decided_ ? blocked_at_ : -1.0; }

 private:
  // The ray's theta bin, computed on first use: most rays meet no static cell before their end,
  // and binOf costs a floating-point remainder.
  int bin() {
    if (bin_ < 0) bin_ = geometry_.binOf(angle_);
    return bin_;
  }

  // A return on static structure, the ray having entered the current structure at a cell that
  // ends it (endsAStructure).
  template <typename ClassOf>
  bool passesAStructureEnd(ClassOf&& class_of) {
    if (ends_on_static_ < 0) {
      ends_on_static_ = class_of(geometry_.cellOf(end_)) == CellClass::kStatic;
    }
    if (ends_on_static_ == 0) return false;
    if (run_enters_at_end_ < 0) {
      run_enters_at_end_ =
          class_of(*run_start_) == CellClass::kStatic && endsAStructure(*run_start_, class_of);
    }
    return run_enters_at_end_ == 1;
  }

  // A ray crossing a one-cell-thick surface passes within half a cell of the centre of one of
  // its cells; a ray that only clips the corner of a structure's end cell never does.
  bool passesNearCentre(const CellIndex& cell) const {
    const Eigen::Vector2d offset = geometry_.cellCenter(cell) - origin_;
    const double distance = std::abs(offset.x() * direction_.y() - offset.y() * direction_.x());
    return distance <= 0.5 * geometry_.resolution();
  }

  // A pane extends on both sides of a ray crossing it; the tip of a structure (a corner, the end
  // of a frame, an edge seen from one side) extends on one side only, and rays passing beside it
  // through the empty part of its cell are not crossing anything.
  template <typename ClassOf>
  bool crossesASurface(const CellIndex& cell, ClassOf&& class_of) const {
    bool left = false, right = false;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        if (!isObstacle(class_of(CellIndex(cell.x() + dx, cell.y() + dy)))) continue;
        const double side = dx * direction_.y() - dy * direction_.x();
        left |= side < 0.0;
        right |= side > 0.0;
      }
    }
    // Obstacles on one side only: a tip. On both sides: a surface. On neither: a lone cell of a
    // surface the field has barely seen (a mirror away from where it was faced): crossed too.
    return left == right;
  }

  const GridGeometry& geometry_;
  Eigen::Vector2d origin_;
  Eigen::Vector2d end_;
  Eigen::Vector2d direction_;
  double angle_;
  bool returned_;  // the ray ends in a return (a hit), not at the clearing distance
  int bin_ = -1;
  int ends_on_static_ = -1;  // whether the ray ends in a static cell; -1 until asked
  // The structure the walk is in: the cell it entered at, and whether that cell ends the
  // structure (-1 until asked).
  std::optional<CellIndex> run_start_;
  int run_enters_at_end_ = -1;
  CellIndex last_visited_ = CellIndex::Zero();
  double last_candidate_ = 0.0;
  double blocked_at_ = -1.0;
  bool decided_ = false;
};

}  // namespace rfm::detail
