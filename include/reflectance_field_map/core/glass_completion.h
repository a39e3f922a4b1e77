#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <cstdint>
#include <vector>

namespace rfm {

// Glass returns only near its normal, so the field sees a facade only where the robot faced it:
// the stretches it only ever saw obliquely read as free space, and whatever lies behind them
// passes the reflection check. Such a stretch still leaves its trace in the field:
//  - it continues a straight run of glass that is missed from many directions (transmission);
//  - it ends at, or is broken by, structure on the same line (frames, mullions, a wall);
//  - it was never looked through near the run's normal, from either face, where glass would
//    have returned.
// A free stretch with all three, no longer than `max_gap` between two pieces of structure, is
// glass the robot has not faced yet. Other panes on the line close a stretch as structure does,
// and the search along the line goes on past them, however long they are. An opening on the line
// that the robot has faced (a door) was missed near the normal and stays open.
// A run whose pane lies on a cell boundary is blurred: a few of its cells lie up to 1.5 cells off
// its line. Its line is less sure, so its walk ends at motion (people on the floor past a pane's
// end), and an unfaced stretch of it longer than 0.5 m stays open when no beam ever ended in it, or
// no more often than beside it: glass seen obliquely still returns now and then on its line (a weak
// echo, dirt scatter), an opening does not, and people walking through it end beams all around
// it. A straight run's stretches close without echoes: clean glass returns none away from its
// normal.
// A pane faced only in passing (a sparse logger, one lidar driving by) can leave nothing that
// anchors it, and motion removal draws its returns motion. A straight run of motion cells that is
// missed from many directions, returned near its normal (within 30 deg) and lies on a line that
// meets structure at both ends within `max_gap`, through free stretches of at most 0.5 m (shorter
// than a doorway) that were never looked through near that normal, is glass, and so are those
// stretches. A trail left by someone walking away from the robot was seen along its line.
class GlassCompletion {
 public:
  // max_gap: m of free cells between two pieces of structure on the line (0: off).
  GlassCompletion(const GridGeometry& geometry, double max_gap);

  // Turns the completed cells of `classes` (the box's classes, row-major) into glass. Returns
  // their indices in `classes`.
  const std::vector<int>& complete(const ReflectanceField& field, const CellBox& box,
                                   std::vector<CellClass>& classes);
  // How many of the last completion's cells were motion (the rest were free).
  size_t turnedFromMotion() const { return turned_from_motion_; }

 private:
  // A straight run of glass: its line, its extent along it and the bins it returns in.
  struct Run {
    Eigen::Vector2d centre;          // m
    Eigen::Vector2d direction;       // unit, along the line
    double first = 0.0, last = 0.0;  // m along `direction` from `centre`
    std::vector<int> return_bins;    // where most of its cells reflect: glass there returns
    std::vector<int> cells;          // its cells' indices in the box
    bool blurred = false;            // a few of its cells lie more than a cell off its line
  };
  // The straight runs of `of_class` cells (glass, or motion that may be glass).
  void collectRuns(const ReflectanceField& field, const CellBox& box,
                   const std::vector<CellClass>& classes, CellClass of_class,
                   std::vector<Run>& runs);
  // The run's line, extent and return bins; false when its cells do not make a straight run of
  // glass.
  bool describeRun(const ReflectanceField& field, const CellBox& box,
                   const std::vector<int>& members, Run& run);
  // Whether `cell` was not looked through in half of the run's return bins, nor in half of the
  // opposite bins (the pane's other face).
  static bool couldBeGlass(const ReflectanceField& field, const Run& run, const CellIndex& cell);
  // Whether the run's return bins lie near its normal, as glass returns.
  bool returnsAcrossLine(const Run& run) const;
  // Whether the line, walked from `from` along `outward` through motion cells and free cells that
  // could be glass (no stretch of them longer than kMaxUnfacedEnd), meets structure (static,
  // glass, metal) within max_gap; the cells walked before it are appended to `walked`.
  bool reachesStructure(const ReflectanceField& field, const CellBox& box, const Run& run,
                        const Eigen::Vector2d& from, const Eigen::Vector2d& outward,
                        const std::vector<CellClass>& classes, std::vector<int>& walked) const;
  // Whether the free cells of `gap` (box indices; `beside` steps across the line) returned as an
  // unfaced pane does now and then (kMinEchoShare), more often than the cells beside the line
  // (kMinEchoContrast), not as an opening.
  bool echoesLikeGlass(const ReflectanceField& field, const CellBox& box,
                       const std::vector<CellClass>& classes, const std::vector<int>& gap,
                       const CellIndex& beside) const;
  void extend(const ReflectanceField& field, const CellBox& box, const Run& run,
              const Eigen::Vector2d& from, const Eigen::Vector2d& outward,
              std::vector<CellClass>& classes, std::vector<int>& completed) const;

  GridGeometry geometry_;
  double max_gap_;
  std::vector<Run> runs_;
  std::vector<Run> motion_runs_;
  std::vector<int> walked_;  // complete(): a motion run's cells and those between it and structure
  size_t turned_from_motion_ = 0;
  std::vector<uint8_t> visited_;  // per box cell, while collecting runs (zero in between)
  std::vector<int> visited_cells_;
  std::vector<int> completed_;
  std::vector<int> bin_counts_;
  std::vector<Eigen::Vector2d> points_;  // describeRun(): the run's cell centres
};

}  // namespace rfm
