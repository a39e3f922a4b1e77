#pragma once

#include "reflectance_field_map/core/anchor_history.h"
#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/circle_fit.h"
#include "reflectance_field_map/core/occupancy.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/reflectance_field.h"
#include "reflectance_field_map/core/zeroed_huge_array.h"

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace rfm {

struct MotionRemovalCounts {
  size_t components = 0;
  size_t static_cells = 0;
  size_t glass_cells = 0;
  size_t metal_cells = 0;
  size_t motion_cells = 0;
  size_t free_cells = 0;
};

// Motion removal (Alg. 2). Nodes are runs of contiguous reflective bins of one cell (theta
// wraps around); two runs of 8-neighbouring cells are connected when their bins are within one
// bin of each other, which is 26-connectivity in (x, y, theta). Components are found with an
// iterative union-find. A component touching a widely visible cell (eq. 7), a known obstacle
// just outside the box, or a cell that the anchor rules let anchor (AnchorHistory: long
// confirmed, never seen through), or one shaped as a round column (AnchorRules::
// column_max_radius_cells), is a static structure: its cells are static (widely visible) or
// glass/metal; any other component is motion. Cells that departed (AnchorHistory) anchor nothing.
// A cell the previous call drew static, glass or metal keeps that class while it still reflects
// and no ray has seen through it since (its missed bins did not grow), even when its component
// no longer is structure (a frame the robot passed, now seen from one side only), unless the
// component arrived as a person does (the share of its runs in solid cells that arrived where
// free space was seen, AnchorRules::solid_min_share).
class MotionRemover {
 public:
  explicit MotionRemover(const OccupancyRule& rule, const AnchorRules& anchors = AnchorRules())
      : rule_(rule), anchors_(anchors) {}

  const AnchorRules& anchors() const { return anchors_; }

  // Classifies every cell of `box` (inside the field's active window) into `classes`
  // (row-major, x fastest). `outside` gives the known class of cells just outside the box and
  // must be safe to call from several threads. With a `runner`, bands of rows are processed
  // on its threads: components are joined within each band, then across band borders.
  // Only tiles holding reflective cells take part in components; the other tiles' cells are
  // free or unknown, and those whose field tile did not change since the previous call on the
  // same field are copied from it (ReflectanceField::tileVersion), not recomputed.
  // `history` is the one kept of the field's cells (AnchorHistory::tick with anchors()).
  MotionRemovalCounts classify(const ReflectanceField& field, const AnchorHistory& history,
                               const CellBox& box,
                               const std::function<CellClass(const CellIndex&)>& outside,
                               std::vector<CellClass>& classes, ParallelRunner* runner = nullptr);

  // After classify: true when the tile holding `cell` (inside the box) was copied from the
  // previous call: its classes, all free or unknown, did not change.
  bool reusedTile(const CellIndex& cell) const {
    return tile_work_[boxTileOf(cell.x(), cell.y())] == TileWork::kReuse;
  }
  // Forgets the previous call's classes: the evidence restarted, and the next call draws only
  // what the new evidence shows.
  void forgetPrevious() {
    previous_field_ = 0;
    previous_box_ = CellBox();
    previous_classes_.clear();
    drawn_.clear();
  }

 private:
  enum class TileWork : uint8_t {
    kComponents,  // holds reflective cells
    kFreeSpace,   // no reflective cell: free or unknown by its missed bins
    kReuse,       // no reflective cell and unchanged: classes copied from the previous call
  };
  struct Run {
    int16_t first_bin;
    int16_t length;  // may wrap past the last bin
  };
  // Rows [first_row, end_row) of the box, relative to box.min.y().
  struct Band {
    int first_row, end_row;
  };
  void collectRuns(const ReflectanceField& field, const CellBox& box, const Band& band,
                   std::vector<Run>& runs);
  void joinBand(const ReflectanceField& field, const AnchorHistory& history, const CellBox& box,
                const Band& band, const std::function<CellClass(const CellIndex&)>& outside);
  // Unites the runs of row `row` with those of the next row (the border between two bands).
  void joinRows(const CellBox& box, int row, int bins);
  void uniteNeighbour(size_t local, size_t n_local, int bins);
  void classifyBand(const ReflectanceField& field, const CellBox& box, const Band& band,
                    std::vector<CellClass>& classes, MotionRemovalCounts& counts,
                    std::vector<size_t>& glass) const;
  // glass_max_static_neighbours: glass and metal cells of band_glass_ against static ones become
  // static.
  void demoteGlassAgainstStructure(const CellBox& box, std::vector<CellClass>& classes,
                                   MotionRemovalCounts& counts) const;
  // Whether the component of `root` spans at least `min_cells` (0: any size).
  bool spansAtLeast(uint32_t root, int min_cells) const;
  // Whether the long-confirmed cells of the component of `root` anchor it: it is long enough
  // (persistence_min_cells) and less than solid_min_share of its runs lie in arrived solid cells.
  bool heldByPersistence(uint32_t root) const;
  // Whether `runs` (per root) hold solid_min_share of the runs of the component of `root`.
  bool holdsSolidShare(const std::vector<uint32_t>& runs, uint32_t root) const;
  // Whether solid cells that arrived hold the share of the component's runs that makes a person.
  bool arrived(uint32_t root) const;
  // Whether the component of any of runs [first, last) (one cell's) arrived.
  bool anyArrived(uint32_t first, uint32_t last) const;
  // The class the previous call drew at `cell` if it was static, glass or metal and the cell's
  // missed bins have not grown past `missed_bins` since; kUnknown otherwise.
  CellClass heldClass(const CellIndex& cell, int missed_bins) const;
  // Keeps the static, glass and metal cells of `classes` (this call's) for heldClass.
  void rememberDrawn(const ReflectanceField& field, const std::vector<CellClass>& classes);
  // Whether the component of `root` is structure: anchored_ (a widely visible anchor, a known
  // obstacle beside the box, a round column, or a solid anchor unless the component departed),
  // long-confirmed cells or its share of solid runs.
  bool isStructure(uint32_t root) const;
  // Whether the component of `root` has as large a share of its runs in solid cells seen gone
  // (CellAnchoring::departed) as makes one structure (solid_min_share): what is left of a person
  // who stood and left, at the cells the robot did not see through again. Its solid anchors
  // anchor nothing.
  bool departed(uint32_t root) const;
  // Anchors the components that are not yet structure and whose runs lie on a round column's
  // rim, each returning along the rim's normal (NormalCircleFit over the runs' central
  // directions).
  void anchorRoundColumns(const ReflectanceField& field, const CellBox& box);

  uint32_t find(uint32_t node);
  void unite(uint32_t a, uint32_t b);
  bool widelyVisible(const ReflectanceField& field, int slot, int reflective_bins) const;
  // Decides each box tile's TileWork and records the tiles' versions for the next call.
  void planTiles(const ReflectanceField& field, const CellBox& box);
  size_t boxTileOf(int x, int y) const {
    return static_cast<size_t>(floorDiv(y, tile_cells_) - first_tile_.y()) * box_tiles_x_ +
           (floorDiv(x, tile_cells_) - first_tile_.x());
  }

  OccupancyRule rule_;
  AnchorRules anchors_;
  int min_widely_visible_bins_ = 0;  // of the field being classified (OccupancyRule)
  std::vector<Run> runs_;
  std::vector<std::vector<Run>> band_runs_;  // per band, before joining into runs_
  std::vector<uint32_t> cell_first_run_;     // CSR over box cells, size cells + 1
  // Per box cell, written and read only in the tiles that hold components (kComponents): a large
  // box's other pages stay unmapped.
  ZeroedHugeArray<int> slots_;  // storage slot of each box cell
  std::vector<uint32_t> parent_;
  std::vector<uint8_t> rank_;
  // Per root, what anchors it: kAnchoredFirmly (a widely visible cell, a known static cell beside
  // the box, a round column's rim), kAnchoredBySolidAngle (a solid cell over a wide angle).
  static constexpr uint8_t kAnchoredFirmly = 1, kAnchoredBySolidAngle = 2;
  std::vector<uint8_t> anchored_;
  std::vector<uint8_t> persistent_;      // per root: holds a long-confirmed cell
  std::vector<uint32_t> runs_in_;        // per root: its runs
  std::vector<uint32_t> solid_runs_;     // per root: its runs in solid cells that anchor
  std::vector<uint32_t> arrived_runs_;   // per root: its runs in solid cells that arrived
  std::vector<uint32_t> departed_runs_;  // per root: its runs in solid cells seen gone
  struct Extent {
    int16_t min_x, min_y, max_x, max_y;  // box-local cells
  };
  std::vector<Extent> extent_;            // per root: bounding box of its cells
  std::vector<uint32_t> root_;            // final root of each run
  ZeroedHugeArray<uint8_t> anchor_cell_;  // per box cell: anchors (widely visible or solid)
  ZeroedHugeArray<uint8_t> solid_;        // per box cell (AnchorRules::solid_max_missed_ratio)
  std::vector<std::vector<size_t>> band_glass_;  // per band: its glass and metal cells

  // Round columns (anchorRoundColumns): a fit per component that is not yet structure.
  std::vector<uint32_t> column_fit_of_root_;  // per root: its index in column_fits_
  std::vector<std::pair<uint32_t, NormalCircleFit>> column_fits_;  // root and fit
  std::vector<double> half_bin_cos_, half_bin_sin_;                // directions at half-bin steps

  // The box's tiles (of the field's window) and what classify does with each.
  int tile_cells_ = 1;
  TileIndex first_tile_{0, 0};
  int box_tiles_x_ = 0;
  std::vector<TileWork> tile_work_;
  // The previous call's result, for tiles that did not change since.
  uint64_t previous_field_ = 0;  // ReflectanceField::identity(), 0: none
  CellBox previous_box_;
  std::vector<CellClass> previous_classes_;
  std::vector<uint32_t> previous_versions_;  // per storage tile, of tiles in previous_box_
  // The previous call's static, glass and metal cells, by index in previous_box_ (ascending),
  // with their missed bins then (heldClass); their classes are in previous_classes_.
  struct DrawnCell {
    uint32_t index;
    uint16_t missed_bins;
  };
  std::vector<DrawnCell> drawn_;
};

// True when circular bin intervals [a, a + a_len) and [b, b + b_len) share a bin.
bool binIntervalsOverlap(int a, int a_len, int b, int b_len, int bins);

}  // namespace rfm
