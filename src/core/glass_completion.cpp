#include "reflectance_field_map/core/glass_completion.h"

#include "reflectance_field_map/core/line_fit.h"
#include "reflectance_field_map/core/ray_traversal.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rfm {
namespace {

// A run shorter than this gives no reliable line.
constexpr size_t kMinRunCells = 8;
// Cells of a straight run lie within this of its line (cells), rasterisation included.
constexpr double kMaxOffLine = 1.0;
// A pane on a cell boundary, its echoes blurred by range noise, leaves a few cells further out: a
// run at least kMinStrayRunLength long may have up to kMaxStrayShare of its cells up to
// kMaxStrayOffLine cells off its line (a blurred run). A short run's line is not sure enough for
// that. A blurred run's line is less sure, so it completes less than a straight run: motion on its
// line (people on the floor past a pane's end) ends the walk instead of framing a gap, and an
// unfaced stretch longer than kMaxUnfacedEnd closes only where it echoed as glass does.
constexpr double kMaxStrayOffLine = 1.5;
constexpr double kMaxStrayShare = 0.1;
constexpr double kMinStrayRunLength = 0.5;  // m
// Glass lets most rays through: its cells are missed from at least this many bins on average.
// A wall seen from a few directions only (narrowly visible too) is missed from almost none.
constexpr double kMinMeanMissedBins = 10.0;
// Structure on the line (frames, mullions) is thin; a longer stretch of it ends the line.
constexpr double kMaxStructure = 0.5;  // m
// Glass returns near its normal: a run of motion cells on a pane was seen across its line. A
// person walking away from the robot leaves a trail seen along it.
const double kMinReturnAcrossLine = std::cos(kPi / 6.0);
// The longest stretch of free cells on the line between a run of motion cells and the structure
// that frames it, or the next run: a part of the pane that the robot did not face. Shorter than a
// doorway, which the robot may not have faced either.
constexpr double kMaxUnfacedEnd = 0.5;  // m
// An unfaced stretch of a blurred run's line longer than a doorway's narrowest (kMaxUnfacedEnd) is
// glass only if beams ended in at least this share of its free cells at some time
// (ReflectanceField::everHitAt), and in one at least: glass seen away from its normal still
// returns now and then (a weak echo, dirt scatter), an opening does not, unless people walk
// through it.
constexpr double kMinEchoShare = 0.1;
// ... and that share is at least this many times the share of the free cells kBesideFrom to
// kBesideTo cells beside it, either side: dirt on a pane ends beams on the pane's line, people
// walking through an opening end them all around it.
constexpr double kMinEchoContrast = 2.0;
constexpr int kBesideFrom = 3, kBesideTo = 6;  // cells

// Whether the cells at `points`, which stray more than kMaxOffLine from `line`, still make a
// (blurred) run: few strays, none far out, on a line long enough to be sure of.
bool straysAreFew(const std::vector<Eigen::Vector2d>& points, const LineFit& line,
                  double resolution) {
  if (line.across > kMaxStrayOffLine * resolution || line.last - line.first < kMinStrayRunLength)
    return false;
  const Eigen::Vector2d normal(-line.direction.y(), line.direction.x());
  size_t strays = 0;
  for (const Eigen::Vector2d& point : points)
    strays += std::abs((point - line.centre).dot(normal)) > kMaxOffLine * resolution;
  return static_cast<double>(strays) <= kMaxStrayShare * static_cast<double>(points.size());
}

}  // namespace

GlassCompletion::GlassCompletion(const GridGeometry& geometry, double max_gap)
    : geometry_(geometry), max_gap_(max_gap) {}

void GlassCompletion::collectRuns(const ReflectanceField& field, const CellBox& box,
                                  const std::vector<CellClass>& classes, CellClass of_class,
                                  std::vector<Run>& runs) {
  runs.clear();
  const int width = box.width(), height = box.height();
  // Glass and motion are rare: jump from one such cell to the next, and clear only the marks set.
  if (visited_.size() != classes.size()) visited_.assign(classes.size(), 0);
  visited_cells_.clear();
  std::vector<int> stack, members;
  const CellClass* const first = classes.data();
  const CellClass* const last = first + classes.size();
  static_assert(sizeof(CellClass) == 1, "searched as bytes");
  for (const CellClass* found = first;
       (found = static_cast<const CellClass*>(
            std::memchr(found, static_cast<int>(of_class), last - found))) != nullptr;
       ++found) {
    const int start = static_cast<int>(found - first);
    if (visited_[start]) continue;
    // 8-connected component of cells of the class.
    visited_[start] = 1;
    collect8Connected(
        width, height, start,
        [&](int n) {
          if (classes[n] != of_class || visited_[n]) return false;
          visited_[n] = 1;
          return true;
        },
        stack, members);
    visited_cells_.insert(visited_cells_.end(), members.begin(), members.end());
    if (members.size() < kMinRunCells) continue;
    Run run;
    if (describeRun(field, box, members, run)) {
      run.cells = members;
      runs.push_back(std::move(run));
    }
  }
  for (int i : visited_cells_)
    visited_[i] = 0;
}

bool GlassCompletion::describeRun(const ReflectanceField& field, const CellBox& box,
                                  const std::vector<int>& members, Run& run) {
  // The line through the cells (principal axis) and how far they stray from it.
  double missed = 0.0;
  points_.clear();
  for (int i : members) {
    points_.push_back(geometry_.cellCenter(box.cellAt(i)));
    missed += field.missedBins(box.cellAt(i));
  }
  missed /= static_cast<double>(members.size());
  const LineFit line = fitLine(points_);
  run.centre = line.centre;
  run.direction = line.direction;
  run.first = line.first;
  run.last = line.last;
  run.blurred = line.across > kMaxOffLine * geometry_.resolution();
  if ((run.blurred && !straysAreFew(points_, line, geometry_.resolution())) ||
      missed < kMinMeanMissedBins)
    return false;
  // Where this glass returns: the bins most of its cells reflect in.
  const int bins = geometry_.thetaBins();
  bin_counts_.assign(bins, 0);
  for (int i : members) {
    forEachMaskBit(field.reflectiveMask(box.cellAt(i)), field.maskWords(),
                   [&](int bin) { ++bin_counts_[bin]; });
  }
  for (int bin = 0; bin < bins; ++bin) {
    if (2 * bin_counts_[bin] >= static_cast<int>(members.size())) run.return_bins.push_back(bin);
  }
  return !run.return_bins.empty();
}

bool GlassCompletion::couldBeGlass(const ReflectanceField& field, const Run& run,
                                   const CellIndex& cell) {
  // Glass on the line would have returned the rays near its normal, from either face: misses
  // there rule it out. At the edges of its lobe glass returns only sometimes (its window
  // jitters), so a cell counts as looked through only where it was missed in half of the run's
  // bins, or of the opposite ones.
  const GridGeometry& geometry = field.geometry();
  size_t missed_facing = 0, missed_behind = 0;
  for (int bin : run.return_bins) {
    missed_facing += field.value(cell, bin) < 0;
    missed_behind += field.value(cell, geometry.binOf(geometry.binCenter(bin) + kPi)) < 0;
  }
  return 2 * std::max(missed_facing, missed_behind) < run.return_bins.size();
}

bool GlassCompletion::returnsAcrossLine(const Run& run) const {
  const Eigen::Vector2d normal(-run.direction.y(), run.direction.x());
  double across = 0.0;
  for (int bin : run.return_bins) {
    const double angle = geometry_.binCenter(bin);
    across += std::abs(normal.x() * std::cos(angle) + normal.y() * std::sin(angle));
  }
  return across >= kMinReturnAcrossLine * static_cast<double>(run.return_bins.size());
}

bool GlassCompletion::reachesStructure(const ReflectanceField& field, const CellBox& box,
                                       const Run& run, const Eigen::Vector2d& from,
                                       const Eigen::Vector2d& outward,
                                       const std::vector<CellClass>& classes,
                                       std::vector<int>& walked) const {
  const Eigen::Vector2d normal(-run.direction.y(), run.direction.x());
  const CellIndex beside =
      std::abs(normal.y()) >= std::abs(normal.x()) ? CellIndex(0, 1) : CellIndex(1, 0);
  auto class_at = [&](const CellIndex& cell) { return classInBox(box, classes, cell); };
  auto any_at = [&](const CellIndex& cell, auto&& is) {
    return is(class_at(cell)) || is(class_at(cell + beside)) || is(class_at(cell - beside));
  };
  bool reached = false;
  double free_from = -1.0;  // where the current stretch of free cells began (m along outward)
  const Eigen::Vector2d to = from + outward * max_gap_;
  forEachCellOnRayWhile(from, to, geometry_.inverseResolution(), [&](const CellIndex& cell) {
    if (!box.contains(cell)) return false;
    if (any_at(cell, [](CellClass c) { return isObstacle(c); })) {
      reached = true;
      return false;
    }
    const CellClass c = class_at(cell);
    const double along = (geometry_.cellCenter(cell) - from).dot(outward);
    if (c == CellClass::kMotion) {
      free_from = -1.0;
    } else if (c == CellClass::kFree && couldBeGlass(field, run, cell)) {
      if (free_from < 0.0) free_from = along;
      if (along - free_from + geometry_.resolution() > kMaxUnfacedEnd) return false;
    } else {
      return false;
    }
    walked.push_back(box.indexOf(cell));
    return true;
  });
  return reached;
}

bool GlassCompletion::echoesLikeGlass(const ReflectanceField& field, const CellBox& box,
                                      const std::vector<CellClass>& classes,
                                      const std::vector<int>& gap, const CellIndex& beside) const {
  const RollingWindow& window = field.window();
  auto free_at = [&](const CellIndex& cell) {
    return box.contains(cell) && classInBox(box, classes, cell) == CellClass::kFree;
  };
  auto echoed_at = [&](const CellIndex& cell) {
    return window.contains(cell) && field.everHitAt(window.storageIndex(cell));
  };
  int free_cells = 0, echoed = 0, beside_cells = 0, beside_echoed = 0;
  for (int i : gap) {
    const CellIndex cell = box.cellAt(i);
    ++free_cells;
    // A free cell beside the line counts for it: the pane may lie a cell off the runs' line.
    bool echoes = false;
    for (const CellIndex& c : {cell, CellIndex(cell + beside), CellIndex(cell - beside)})
      echoes = echoes || (free_at(c) && echoed_at(c));
    echoed += echoes;
    for (int k = kBesideFrom; k <= kBesideTo; ++k) {
      for (const CellIndex& c : {CellIndex(cell + k * beside), CellIndex(cell - k * beside)}) {
        if (!free_at(c)) continue;
        ++beside_cells;
        beside_echoed += echoed_at(c);
      }
    }
  }
  // Shares compared without division: echoed / free >= contrast * beside_echoed / beside_cells.
  return echoed > 0 && echoed >= kMinEchoShare * free_cells &&
         static_cast<double>(echoed) * beside_cells >=
             kMinEchoContrast * beside_echoed * static_cast<double>(free_cells);
}

void GlassCompletion::extend(const ReflectanceField& field, const CellBox& box, const Run& run,
                             const Eigen::Vector2d& from, const Eigen::Vector2d& outward,
                             std::vector<CellClass>& classes, std::vector<int>& completed) const {
  const double resolution = geometry_.resolution();
  const Eigen::Vector2d normal(-run.direction.y(), run.direction.x());
  // Structure beside the line by a cell still counts as on it (rasterisation).
  const CellIndex beside =
      std::abs(normal.y()) >= std::abs(normal.x()) ? CellIndex(0, 1) : CellIndex(1, 0);
  auto class_at = [&](const CellIndex& cell) { return classInBox(box, classes, cell); };
  // Anything reflective: frames glimpsed from a few directions only are left as motion by
  // Alg. 2 (nothing widely visible anchors them), yet they still mark the line.
  auto structure_at = [&](const CellIndex& cell) {
    const CellClass c = class_at(cell);
    return isObstacle(c) || c == CellClass::kMotion;
  };
  auto glass_at = [&](const CellIndex& cell) { return class_at(cell) == CellClass::kGlass; };
  auto obstacle_at = [&](const CellIndex& cell) { return isObstacle(class_at(cell)); };
  std::vector<int> gap;
  Eigen::Vector2d gap_start;
  // Motion cells of the structure the gap began at: between two stretches of glass they are
  // part of the line (a frame), and glass too once the gap closes.
  std::vector<int> framing;
  int structure = 0;  // cells in the current stretch of structure
  auto turn_to_glass = [&](std::vector<int>& cells) {
    for (int i : cells) {
      if (classes[i] == CellClass::kGlass) continue;  // listed twice (a diagonal line)
      classes[i] = CellClass::kGlass;
      completed.push_back(i);
    }
    cells.clear();
  };
  // A facade of a few panes between mullions; the walk ends long before on anything else.
  const Eigen::Vector2d to = from + outward * (8.0 * max_gap_ + 1.0);
  auto close_gap = [&] {
    if (gap.empty()) return;
    const double length =
        (geometry_.cellCenter(box.cellAt(gap.back())) - gap_start).dot(outward) + resolution;
    if (run.blurred && length > kMaxUnfacedEnd &&
        !echoesLikeGlass(field, box, classes, gap, beside)) {
      gap.clear();  // an opening: the walk goes on to the panes beyond it
      return;
    }
    turn_to_glass(gap);
    turn_to_glass(framing);
  };
  forEachCellOnRayWhile(from, to, geometry_.inverseResolution(), [&](const CellIndex& cell) {
    if (!box.contains(cell)) return false;
    // More panes of the line, whether or not they make a run of their own: like a frame they
    // close the gap before them, and however long they are the walk goes on past them.
    if (glass_at(cell) || glass_at(cell + beside) || glass_at(cell - beside)) {
      close_gap();
      framing.clear();
      structure = 0;
      return true;
    }
    if (structure_at(cell) || structure_at(cell + beside) || structure_at(cell - beside)) {
      // A blurred run's line is less sure: motion on it may be people past the pane's end.
      if (run.blurred && !obstacle_at(cell) && !obstacle_at(cell + beside) &&
          !obstacle_at(cell - beside)) {
        return false;
      }
      close_gap();  // structure closes the gap before it
      if (structure == 0) framing.clear();
      for (const CellIndex& c : {CellIndex(cell - beside), cell, CellIndex(cell + beside)}) {
        if (class_at(c) == CellClass::kMotion) framing.push_back(box.indexOf(c));
      }
      return ++structure * resolution <= kMaxStructure;
    }
    structure = 0;
    const int i = box.indexOf(cell);
    if (classes[i] != CellClass::kFree || !couldBeGlass(field, run, cell)) return false;
    if (gap.empty()) gap_start = geometry_.cellCenter(cell);
    gap.push_back(i);
    return (geometry_.cellCenter(cell) - gap_start).dot(outward) + resolution <= max_gap_;
  });
}

const std::vector<int>& GlassCompletion::complete(const ReflectanceField& field, const CellBox& box,
                                                  std::vector<CellClass>& classes) {
  std::vector<int>& completed = completed_;
  completed.clear();
  if (max_gap_ <= 0.0) return completed;
  collectRuns(field, box, classes, CellClass::kGlass, runs_);
  // A pane faced only briefly (a sparse logger, a single pass) anchors on nothing that Alg. 2
  // knows of and falls as motion. Its run lies on the line between structure, seen across it,
  // and the stretches between it and that structure were never looked through near its normal.
  turned_from_motion_ = 0;
  collectRuns(field, box, classes, CellClass::kMotion, motion_runs_);
  for (const Run& run : motion_runs_) {
    walked_.clear();
    if (!returnsAcrossLine(run) ||
        !reachesStructure(field, box, run, run.centre + run.direction * run.last, run.direction,
                          classes, walked_) ||
        !reachesStructure(field, box, run, run.centre + run.direction * run.first, -run.direction,
                          classes, walked_)) {
      continue;
    }
    walked_.insert(walked_.end(), run.cells.begin(), run.cells.end());
    for (int i : walked_) {
      if (classes[i] == CellClass::kGlass) continue;  // listed twice (a diagonal line)
      turned_from_motion_ += classes[i] == CellClass::kMotion;
      classes[i] = CellClass::kGlass;
      completed.push_back(i);
    }
  }
  // From both ends of every run, outwards along its line.
  for (const Run& run : runs_) {
    extend(field, box, run, run.centre + run.direction * run.last, run.direction, classes,
           completed);
    extend(field, box, run, run.centre + run.direction * run.first, -run.direction, classes,
           completed);
  }
  return completed;
}

}  // namespace rfm
