// The reflection check of Alg. 3 for one ray, fed the cells along it (ReflectionRemover).
#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

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
// with the map. Nor does one block such a return where the ray comes out of the structure on the
// side it went in (cameOutWhereItEntered): it clipped a jamb or a pillar that drift or a blurred
// edge drew a cell wider than it is. Passing through means crossing it: the ray comes out into a
// non-obstacle cell more than `penetration_tolerance` before its end. A ray grazing along a wall
// stays inside the wall's cells up to its end, and a ray ending on a surface ends within the
// tolerance: neither counts.
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
        if (!(in_run_ && std::abs(cell.x() - last_visited_.x()) <= 1 &&
              std::abs(cell.y() - last_visited_.y()) <= 1)) {
          run_start_ = cell;
          in_run_ = true;
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
        blocked_at_static_ = returned_ && c == CellClass::kStatic;
      }
    } else if (!isObstacle(c)) {
      if (blocked_at_static_ && endsOnStatic(class_of) &&
          cameOutWhereItEntered(run_start_, cell, class_of)) {
        blocked_at_ = -1.0;  // passed beside the structure, not through it
        in_run_ = false;
        return true;
      }
      decided_ = true;  // came out on the other side
      return false;
    } else if (isGlassOrMetal(c)) {
      blocked_at_static_ = false;  // a pane behind its frame: cut as before
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

  // Whether the ray ends in a static cell (asked once, when needed).
  template <typename ClassOf>
  bool endsOnStatic(ClassOf&& class_of) {
    if (ends_on_static_ < 0) {
      ends_on_static_ = class_of(geometry_.cellOf(end_)) == CellClass::kStatic;
    }
    return ends_on_static_ == 1;
  }

  // A return on static structure, the ray having entered the current structure at a cell that
  // ends it (endsAStructure).
  template <typename ClassOf>
  bool passesAStructureEnd(ClassOf&& class_of) {
    if (!endsOnStatic(class_of)) return false;
    if (run_enters_at_end_ < 0) {
      run_enters_at_end_ =
          class_of(run_start_) == CellClass::kStatic && endsAStructure(run_start_, class_of);
    }
    return run_enters_at_end_ == 1;
  }

  // Whether the cell before `run_start`, where the ray went into the structure, and `exit`, the
  // first cell after it, are joined by non-obstacle cells (4-neighbours) within the box around
  // both widened by a cell: the ray then clipped a tip or a flank (a jamb or a pillar drawn a
  // cell wider than it is, as drift leaves them) and came out on the side it entered from. A
  // surface crossed parts the two; a box wider than kMaxBox cells (the ray walked through the
  // structure for a metre or more) counts as crossed.
  template <typename ClassOf>
  bool cameOutWhereItEntered(const CellIndex& run_start, const CellIndex& exit,
                             ClassOf&& class_of) const {
    constexpr int kMaxBox = 24;
    const double step = 0.25 * geometry_.resolution();
    const double start = (geometry_.cellCenter(run_start) - origin_).dot(direction_);
    CellIndex entry = run_start;
    bool found = false;
    for (int k = 1; k <= 12 && !found; ++k) {  // back along the ray, up to three cells
      entry = geometry_.cellOf(origin_ + direction_ * (start - step * k));
      found = !isObstacle(class_of(entry));
    }
    if (!found) return false;
    const int min_x = std::min(entry.x(), exit.x()) - 1, min_y = std::min(entry.y(), exit.y()) - 1;
    const int width = std::max(entry.x(), exit.x()) + 2 - min_x;
    const int height = std::max(entry.y(), exit.y()) + 2 - min_y;
    if (width > kMaxBox || height > kMaxBox) return false;
    uint8_t reached[kMaxBox * kMaxBox] = {};
    CellIndex queue[kMaxBox * kMaxBox];
    int head = 0, tail = 0;
    queue[tail++] = entry;
    reached[(entry.y() - min_y) * width + entry.x() - min_x] = 1;
    while (head < tail) {
      const CellIndex at = queue[head++];
      if (at == exit) return true;
      const CellIndex steps[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      for (const CellIndex& s : steps) {
        const CellIndex next = at + s;
        const int x = next.x() - min_x, y = next.y() - min_y;
        if (x < 0 || x >= width || y < 0 || y >= height || reached[y * width + x]) continue;
        if (isObstacle(class_of(next))) continue;
        reached[y * width + x] = 1;
        queue[tail++] = next;
      }
    }
    return false;
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
  // The structure the walk is in (in_run_): the cell it entered at, and whether that cell ends
  // the structure (-1 until asked).
  CellIndex run_start_ = CellIndex::Zero();
  bool in_run_ = false;
  int run_enters_at_end_ = -1;
  bool blocked_at_static_ = false;  // a return blocked at a static cell (it may pass beside it)
  CellIndex last_visited_ = CellIndex::Zero();
  double last_candidate_ = 0.0;
  double blocked_at_ = -1.0;
  bool decided_ = false;
};

}  // namespace rfm::detail
