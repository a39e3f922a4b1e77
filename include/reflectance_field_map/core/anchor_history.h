// The anchors of motion removal (Alg. 2) beyond the paper's widely visible cells, and the
// per-cell histories they read.
#pragma once

#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/occupancy.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/reflectance_field.h"
#include "reflectance_field_map/core/rolling_window.h"
#include "reflectance_field_map/core/zeroed_huge_array.h"

#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace rfm {

class AnchorHistory;

// What the rules make of one reflective cell.
struct CellAnchoring {
  bool anchor = false;      // widely visible, or solid over a wide angle, and still there: anchors,
                            // and is drawn static
  bool persistent = false;  // confirmed for long and still there (persistence_min_cells)
  bool solid = false;       // missed in few bins for its reflective ones (solid_max_missed_ratio)
  bool solid_anchor = false;  // solid, and neither departed nor arrived: counts towards the share
  bool arrived = false;       // solid, not departed, and arrived (AnchorHistory::arrivedAt): counts
                              // against the persistent cells of its component
  bool widely_visible = false;  // an anchor by eq. 7 (not only by its solid angle)
  bool departed = false;  // solid, and departed or abandoned: seen gone; counts against the solid
                          // anchors of its component
};

// The rules in the units the history counts in (ticks of the persistence clock, cells, theta
// bins). 0 switches a rule off.
struct AnchorRules {
  // Cells confirmed for this many persistence ticks anchor their component too
  // (AnchorHistory::confirmedTicksAt): a sensor that does not move sees walls from one side.
  int persistence_ticks = 0;
  // ... but only components at least this long (bounding box side, in cells): a person
  // standing still is smaller than structure.
  int persistence_min_cells = 0;
  // Widely visible or confirmed cells with this many contradicted bins
  // (AnchorHistory::contradictedBinsAt) anchor nothing: what stood there has left.
  int departure_min_bins = 0;
  // Nor do those vacant for this many ticks (AnchorHistory::vacantTicksAt): seen through
  // from new directions and hit by nothing, as when the robot looks back at where a person
  // stood from directions it never saw them from.
  int departure_vacant_ticks = 0;
  // ... and over at least this many scans (AnchorHistory::vacantScansAt): sparse scans (a
  // logger keeping one every metre) tick once a scan, and two glimpses through a wall prove
  // nothing.
  int departure_vacant_scans = 0;
  // A hit within this many cells (Chebyshev) of a cell keeps it from being vacant at that tick:
  // structure in view is hit somewhere near it. A round column returns only along its normal,
  // so the robot sees through the cells of its rim on the sides and hits the side it faces.
  int vacancy_hit_radius = 0;
  // A widely visible cell anchors nothing once it arrived where the field had seen it free
  // while missed in at least this many bins (AnchorHistory::arrivedWidelyAt): someone who
  // walked onto floor seen from all round and stood while the robot drove round them. 0: off.
  int wide_arrival_min_missed_bins = 0;
  // A reflective cell missed in at most this many bins per reflective bin is solid: it returns
  // from nearly wherever it is seen. Moving objects are seen through where they were, glass and
  // metal away from their lobe, so their cells are missed in many more bins (0: off).
  double solid_max_missed_ratio = 0.0;
  // A component at least this share of whose runs lie in solid cells is structure, unless those
  // cells departed or arrived (AnchorHistory::arrivedAt): it needs no widely visible cell, which
  // sparse scans never make.
  double solid_min_share = 0.5;
  // Such a cell (solid, neither departed nor arrived) with this many reflective bins anchors its
  // component as a widely visible one does (0: off).
  int solid_anchor_min_bins = 0;
  // Glass is a thin surface with open space on both sides. A cell that would be glass or metal
  // with more static neighbours (of 8) than this lies against structure: it is that structure's
  // surface, blurred by pose error, and static. Negative: off.
  int glass_max_static_neighbours = -1;
  // A component that no other rule anchors and whose cells lie on a circle of at most this
  // radius (cells), each returning along its normal from outside, is a round column (0: off).
  double column_max_radius_cells = 0.0;

  // Which cells keep a history. Cells with at least this many reflective bins at a tick
  // remember those bins (departures); max: none.
  int remembered_min_bins = std::numeric_limits<int>::max();
  // Cells with at least this many reflective bins at a tick could be widely visible
  // (AnchorHistory::rememberedWideAt): departures of cells merely confirmed read only theirs.
  int wide_min_bins = std::numeric_limits<int>::max();
  // Cells confirmed for at least this many ticks remember the bins they are certain in
  // (abandonment); 0: none.
  int confirmed_min_ticks = 0;

  // The rules of `options` for a field of `geometry` whose bins `model` updates; `rule` tells
  // which cells could be widely visible.
  static AnchorRules fromOptions(const MotionRemovalOptions& options, const GridGeometry& geometry,
                                 const OccupancyRule& rule, const LogOddsModel& model);
  // Component extents are needed only by the rules with a minimum length.
  bool tracksExtents() const { return persistence_min_cells > 0; }

  // The rules applied to a reflective cell of `field` with `reflective_bins` bins,
  // `widely_visible` by eq. 7, and the history `history` kept of it.
  CellAnchoring judge(const ReflectanceField& field, const AnchorHistory& history,
                      int storage_index, int reflective_bins, bool widely_visible) const;
};

// Per-cell histories of the active region that the anchor rules read, updated at persistence
// ticks (on the scans' clock, motion_removal_rate):
//  - confirmed ticks: grow while a cell stays reflective and is hit again between ticks,
//    saturating at 255, and reset when it stops being reflective;
//  - departure history (cells with at least remembered_min_bins reflective bins): the bins they
//    were reflective in at some tick, and their vacancy (see vacantTicksAt);
//  - certainty history (cells confirmed for confirmed_min_ticks): the bins they were certain in,
//    and their abandonment (see abandonedTicksAt).
// The histories summarise the active region only: tiles that leave it forget them.
class AnchorHistory {
 public:
  explicit AnchorHistory(const ReflectanceField& field);

  // A persistence tick: reads what the field changed since the last one (hits, mask changes)
  // and clears that record. `rules` say which cells keep a history (remembered_min_bins,
  // confirmed_min_ticks). With a runner, on its threads.
  // `scans` were inserted since the last tick.
  void tick(ReflectanceField& field, const AnchorRules& rules, ParallelRunner* runner = nullptr,
            int scans = 1);
  // The tiles left the active region (ReflectanceField::recenter): their cells start afresh.
  void forgetTiles(const std::vector<TileIndex>& tiles, const RollingWindow& window);
  void clear();

  int confirmedTicksAt(int storage_index) const { return confirmed_ticks_[storage_index]; }
  // Whether the cell became reflective after it was seen free (missed, nothing reflective) at a
  // tick: something arrived where there was nothing. Cleared when it stops being reflective.
  bool arrivedAt(int storage_index) const { return (arrival_[storage_index] & kArrived) != 0; }
  // ... after it was seen free while missed in AnchorRules::wide_arrival_min_missed_bins bins.
  bool arrivedWidelyAt(int storage_index) const {
    return (arrival_[storage_index] & kArrivedWidely) != 0;
  }
  // Bins of the cell that were reflective at a tick and are now missed with at least half the
  // clamp's confidence: something that was seen there is gone (a person who stood still, then
  // left). 0 for cells without history. Static structure, opaque, is not seen through from a
  // direction it reflected in.
  int contradictedBinsAt(const ReflectanceField& field, int storage_index) const;
  // Consecutive ticks, up to the last, over which the cell got new missed bins and no hit: it is
  // seen through from new directions and nothing there or near it (vacancy_hit_radius) reflects
  // any more (a person who stood still seen from elsewhere after leaving). A hit resets it:
  // structure in view is hit, even where grazing rays pass through its cell. 0 for cells
  // without history.
  int vacantTicksAt(int storage_index) const;
  // The scans inserted over those ticks (up to 255).
  int vacantScansAt(int storage_index) const;
  // Whether the cell had at a tick as many reflective bins as a widely visible cell needs
  // (AnchorRules::wide_min_bins).
  bool rememberedWideAt(int storage_index) const;
  // Consecutive ticks, up to the last, over which a confirmed cell was missed in a bin it had
  // been certain in and hit nowhere: the robot looks through it from where it saw it solid (a
  // person who stood still for long, then left). Glass transmits only away from the directions
  // it returns in, and structure in view is hit. 0 for cells without that history.
  int abandonedTicksAt(int storage_index) const;

  // Memory of the confirmed ticks and the histories (hash map overhead estimated).
  size_t bytes() const;

 private:
  struct DepartureHistory {
    std::vector<uint64_t> bins;   // reflective at a tick (mask words)
    uint16_t missed_at_tick = 0;  // missed bins at the last tick
    uint8_t vacant_ticks = 0;
    uint8_t vacant_scans = 0;
    bool wide = false;  // had wide_min_bins reflective bins at a tick
  };
  struct CertaintyHistory {
    std::vector<uint64_t> certain;  // bins at the clamp at a tick while confirmed (mask words)
    std::vector<int8_t> at_tick;    // by bin: a certain bin's log-odds at the last tick
    uint8_t abandoned_ticks = 0;
  };
  // The arrival state of a cell reflective in no bin: seen free once it got a bin missed with
  // at least half the clamp's confidence (ReflectanceField::confidentlyMissedSinceTick), seen
  // free widely if it was then missed in `min_missed_bins` bins or more (0: never).
  static uint8_t seenFree(const ReflectanceField& field, int slot, uint8_t arrival,
                          int min_missed_bins);
  void addReflectiveBins(const ReflectanceField& field, size_t storage_index, int wide_min_bins,
                         DepartureHistory& history) const;
  void addCertainBins(const ReflectanceField& field, size_t storage_index,
                      CertaintyHistory& history) const;

  int mask_words_;
  int theta_bins_;
  // Per cell, zero where the ticks never reached (untouched pages stay unmapped).
  ZeroedHugeArray<uint8_t> confirmed_ticks_;  // by storage index
  // The arrival state of a cell now reflective: seen free (widely) becomes arrived (widely).
  static uint8_t arrive(uint8_t arrival);
  static constexpr uint8_t kSeenFree = 1, kArrived = 2, kSeenFreeWidely = 4, kArrivedWidely = 8;
  // By storage index: kSeenFree or kArrived, kSeenFreeWidely or kArrivedWidely.
  ZeroedHugeArray<uint8_t> arrival_;
  std::unordered_map<int, DepartureHistory> departure_;  // by storage index
  std::unordered_map<int, CertaintyHistory> certainty_;  // by storage index
};

}  // namespace rfm
