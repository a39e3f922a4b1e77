// Glass and metal are kept only where they lie on a pane; the rest is drawn static.
#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/grid_geometry.h"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <unordered_map>
#include <vector>

namespace rfm {

// Glass is a pane, and a pane is thin and straight: in the scan's plane, a line of obstacle cells
// (its glass, its frames, the wall it is set in). Cells seen from a narrow range of directions
// that lie on no such line are returns from clutter, from something seen from one place only or
// from the rough face of a thick wall: drawn static, and Alg. 3 has no reason to distrust a ray
// that passed them (a static cell reflective over less than static_blocking_min_angle, as they
// are, cuts only rays without a return).
//
// A cell lies on a pane when the obstacle cells 8-connected to it within kWindowRadius cells lie
// within kMaxHalfThickness cells of their principal line and span at least kMinLength cells
// along it. Its pane's glass is also at least kMinGlassCells glass or metal cells 8-connected:
// a speck of one to three cells on a wall's line is the wall's face, seen through by rays that
// graze it, not a pane. And a cell of a pane that reflects at all reflects near the pane's
// normal: glass returns within a few degrees of it, metal within its lobe. A line seen only
// obliquely is the image of a wall in a pane or a mirror (the folded rays draw it where nothing
// is, the same from wherever they bounce) or a wall's face seen grazing, not glass.
class PaneShape {
 public:
  static constexpr int kWindowRadius = 4;
  static constexpr double kMinLength = 5.0;
  static constexpr double kMaxHalfThickness = 2.5;
  // A pane's glass (or metal) cells: at least this many 8-connected.
  static constexpr int kMinGlassCells = 4;
  // A pane's glass (or metal) cell reflects in some direction within this angle of the pane's
  // normal (35 deg, rad).
  static constexpr double kMaxLobeOffNormal = 0.6108652381980153;

  // The direction (unit, cells) of the pane the cell lies on, or none when it lies on no pane;
  // class_at(CellIndex) gives any cell's class (unknown where nothing is known).
  template <typename ClassAt>
  std::optional<Eigen::Vector2d> paneDirection(const CellIndex& cell, ClassAt&& class_at);

  // Whether the glass or metal cell `index` of `classes` (row-major over `box`) lies in an
  // 8-connected group of at least kMinGlassCells glass and metal cells. A group is measured once,
  // at the first of its cells asked about, and remembered until forgetGroups().
  bool inPaneSizedGroup(const CellBox& box, const std::vector<CellClass>& classes, int index);
  void forgetGroups();

 private:
  enum GroupMark : uint8_t { kSmallGroup, kPaneSizedGroup };
  static constexpr int kSide = 2 * kWindowRadius + 1;
  static int local(int dx, int dy) { return (dy + kWindowRadius) * kSide + dx + kWindowRadius; }
  // The direction of the line members_ lie along, when they line up as a pane's cells do.
  std::optional<Eigen::Vector2d> lineUp() const;

  std::array<uint8_t, kSide * kSide> seen_{};
  std::vector<Eigen::Vector2d> members_;  // offsets (cells) from the cell judged
  std::vector<int> stack_;                // scratch of paneDirection and of measuring a group
  // The glass and metal cells measured since forgetGroups(): few, where an array over the box
  // would take a byte for each of its cells.
  std::unordered_map<int, GroupMark> group_of_;
  std::vector<int> group_;  // the group last measured
};

// The cells drawStaticOffPane changed: indices in `classes`, ascending, and how many of them were
// glass and how many metal.
struct OffPaneCells {
  std::vector<int> cells;
  size_t glass = 0, metal = 0;
};

// Whether a cell of `classes` (by index) reflects in some direction within `max_off` (rad) of the
// axis `normal` (unit, either way along it), or reflects in none (glass completed where the robot
// never faced it).
using FacesNormal = std::function<bool(int index, const Eigen::Vector2d& normal, double max_off)>;

// Draws the glass and metal cells of `classes` (row-major over `box`) that lie on no pane, or in a
// speck of fewer than PaneShape::kMinGlassCells, or that do not face their pane (`faces_normal`,
// when given), static; cells outside the box count as unknown. Specks are found in the classes as
// given, and a cell drawn static stays an obstacle, so the result does not depend on the order of
// cells.
OffPaneCells drawStaticOffPane(const CellBox& box, std::vector<CellClass>& classes,
                               PaneShape& panes, const FacesNormal& faces_normal = {});

template <typename ClassAt>
std::optional<Eigen::Vector2d> PaneShape::paneDirection(const CellIndex& cell, ClassAt&& class_at) {
  auto obstacle = [](CellClass c) { return c == CellClass::kStatic || isGlassOrMetal(c); };
  // The obstacle cells connected to the cell inside the window, as offsets from it.
  seen_.fill(0);
  members_.clear();
  stack_.assign(1, local(0, 0));
  seen_[local(0, 0)] = 1;
  while (!stack_.empty()) {
    const int l = stack_.back();
    stack_.pop_back();
    const int dx = l % kSide - kWindowRadius, dy = l / kSide - kWindowRadius;
    members_.emplace_back(dx, dy);
    for (int ny = std::max(dy - 1, -kWindowRadius); ny <= std::min(dy + 1, kWindowRadius); ++ny) {
      for (int nx = std::max(dx - 1, -kWindowRadius); nx <= std::min(dx + 1, kWindowRadius); ++nx) {
        if (seen_[local(nx, ny)]) continue;
        seen_[local(nx, ny)] = 1;
        if (obstacle(class_at(CellIndex(cell.x() + nx, cell.y() + ny))))
          stack_.push_back(local(nx, ny));
      }
    }
  }
  return lineUp();
}

}  // namespace rfm
