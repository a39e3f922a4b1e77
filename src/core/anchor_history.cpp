#include "reflectance_field_map/core/anchor_history.h"

#include <algorithm>
#include <cmath>

namespace rfm {
namespace {

// How many whole `unit`s cover `value` (rounded up; exact multiples are not rounded past).
int unitsIn(double value, double unit) {
  return static_cast<int>(std::ceil(value / unit - 1e-9));
}

// How near a hit keeps a cell from being vacant (m): the side of a round column facing the robot,
// from the cells of its rim the robot sees through (a 20 cm column of the tuning scenes needed 5
// cells; 3 lost part of it), and a wall surface blurred by pose error.
constexpr double kVacancyHitRadius = 0.25;

// Vacancy takes at least this many scans as well as departure_vacant_time: a logger that keeps a
// scan every metre ticks once a scan. On the freiburg-campus log a 3 m line of wall seen through
// by a few such scans, with nothing near it hit, was dropped after two. Two 40 Hz lidars make 80
// scans a second, so dense data never waits for this.
constexpr int kDepartureVacantMinScans = 4;

// A widely visible cell anchors nothing where it arrived after the field saw it free while missed
// over at least this angle (rad, 20 deg): floor seen all round, where someone walked in and stood
// while the robot drove round them. A wall's cell that rays running along the wall crossed before
// they hit it is missed over a few degrees: at 10 deg panes lost the frames that carry them
// (doc/design.md).
constexpr double kWideArrivalMinMissedAngle = 0.3490658503988659;

// Whether the cell in `slot`, or one within `radius` cells of it in the window, was hit since
// the last tick.
bool hitNear(const ReflectanceField& field, int slot, int radius) {
  const RollingWindow& window = field.window();
  const CellIndex cell = window.cellOfSlot(slot);
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      const CellIndex near = cell + CellIndex(dx, dy);
      if (window.contains(near) && field.hitSinceTick(window.storageIndex(near))) return true;
    }
  }
  return false;
}

}  // namespace

AnchorRules AnchorRules::fromOptions(const MotionRemovalOptions& options,
                                     const GridGeometry& geometry, const OccupancyRule& rule,
                                     const LogOddsModel& model) {
  const double tick = 1.0 / options.motion_removal_rate;
  AnchorRules rules;
  rules.persistence_ticks = unitsIn(options.persistence_time, tick);
  rules.persistence_min_cells = unitsIn(options.persistence_min_length, geometry.resolution());
  rules.departure_min_bins = unitsIn(options.departure_min_angle, geometry.binWidth());
  rules.departure_vacant_ticks = unitsIn(options.departure_vacant_time, tick);
  rules.departure_vacant_scans = kDepartureVacantMinScans;
  rules.solid_max_missed_ratio = options.solid_max_missed_ratio;
  rules.solid_min_share = options.solid_min_share;
  rules.solid_anchor_min_bins = unitsIn(options.solid_anchor_min_angle, geometry.binWidth());
  rules.glass_max_static_neighbours = options.glass_max_static_neighbours;
  rules.column_max_radius_cells = options.column_max_radius / geometry.resolution();
  rules.vacancy_hit_radius = unitsIn(kVacancyHitRadius, geometry.resolution());
  rules.wide_arrival_min_missed_bins = unitsIn(kWideArrivalMinMissedAngle, geometry.binWidth());
  // Departures read the history of the cells reflective in as many bins as a departure needs
  // contradicted: those that could be widely visible, and the solid cells of a person seen from
  // one side, who anchor their component as structure until they are seen gone. Of cells merely
  // confirmed for the persistence time only if they could be widely visible: glass confirmed
  // that way is seen through in its jittered lobe's edge bins later, and from new directions
  // with nothing near it hit, which reads as a departure.
  if (rules.departure_min_bins > 0 || rules.departure_vacant_ticks > 0) {
    rules.remembered_min_bins = std::max(1, rules.departure_min_bins);
    rules.wide_min_bins = rule.minWidelyVisibleBins(model, geometry.thetaBins());
  }
  // Those confirmed cells are watched only in the bins they were certain in, which glass
  // keeps returning in (abandonedTicksAt).
  if (rules.departure_vacant_ticks > 0) rules.confirmed_min_ticks = rules.persistence_ticks;
  return rules;
}

AnchorHistory::AnchorHistory(const ReflectanceField& field)
    : mask_words_(field.maskWords()),
      theta_bins_(field.geometry().thetaBins()),
      confirmed_ticks_(static_cast<size_t>(field.window().sizeCells()) * field.window().sizeCells(),
                       PageKind::kOrdinary),
      arrival_(confirmed_ticks_.size(), PageKind::kOrdinary) {}

CellAnchoring AnchorRules::judge(const ReflectanceField& field, const AnchorHistory& history,
                                 int slot, int reflective_bins, bool widely_visible) const {
  const bool confirmed =
      persistence_ticks > 0 && history.confirmedTicksAt(slot) >= persistence_ticks;
  const bool solid = solid_max_missed_ratio > 0.0 &&
                     field.missedBinsAt(slot) <= solid_max_missed_ratio * reflective_bins;
  // Only a would-be anchor needs its history read.
  const bool departed =
      (widely_visible || solid || (confirmed && history.rememberedWideAt(slot))) &&
      ((departure_min_bins > 0 && history.contradictedBinsAt(field, slot) >= departure_min_bins) ||
       (departure_vacant_ticks > 0 && history.vacantTicksAt(slot) >= departure_vacant_ticks &&
        history.vacantScansAt(slot) >= departure_vacant_scans));
  // Evidence confirmed for long, or solid, anchors until the robot looks through it from where it
  // saw it solid.
  const bool abandoned = (confirmed || solid) && departure_vacant_ticks > 0 &&
                         history.abandonedTicksAt(slot) >= departure_vacant_ticks;
  CellAnchoring anchoring;
  const bool still_there = solid && !departed && !abandoned;
  const bool solid_anchor = still_there && !history.arrivedAt(slot);
  // Seen all round where it now reflects: someone who walked in and stood, not structure.
  const bool wide = widely_visible && !departed && !history.arrivedWidelyAt(slot);
  anchoring.anchor = wide || (solid_anchor && solid_anchor_min_bins > 0 &&
                              reflective_bins >= solid_anchor_min_bins);
  anchoring.persistent = confirmed && !departed && !abandoned;
  anchoring.solid = solid;
  anchoring.solid_anchor = solid_anchor;
  anchoring.arrived = still_there && history.arrivedAt(slot);
  anchoring.widely_visible = wide;
  anchoring.departed = solid && (departed || abandoned);
  return anchoring;
}

uint8_t AnchorHistory::seenFree(const ReflectanceField& field, int slot, uint8_t arrival,
                                int min_missed_bins) {
  // Seen free once (a person who then left was seen free before arriving) stays seen free.
  const bool confident = field.confidentlyMissedSinceTick(slot);
  const bool widely =
      confident && min_missed_bins > 0 && field.missedBinsAt(slot) >= min_missed_bins;
  uint8_t seen = 0;
  if ((arrival & (kSeenFree | kArrived)) || confident) seen |= kSeenFree;
  if ((arrival & (kSeenFreeWidely | kArrivedWidely)) || widely) seen |= kSeenFreeWidely;
  return seen;
}

uint8_t AnchorHistory::arrive(uint8_t arrival) {
  if (arrival & kSeenFree) arrival = (arrival & ~kSeenFree) | kArrived;
  if (arrival & kSeenFreeWidely) arrival = (arrival & ~kSeenFreeWidely) | kArrivedWidely;
  return arrival;
}

int AnchorHistory::vacantTicksAt(int storage_index) const {
  const auto it = departure_.find(storage_index);
  return it == departure_.end() ? 0 : it->second.vacant_ticks;
}

int AnchorHistory::vacantScansAt(int storage_index) const {
  const auto it = departure_.find(storage_index);
  return it == departure_.end() ? 0 : it->second.vacant_scans;
}

bool AnchorHistory::rememberedWideAt(int storage_index) const {
  const auto it = departure_.find(storage_index);
  return it != departure_.end() && it->second.wide;
}

int AnchorHistory::abandonedTicksAt(int storage_index) const {
  const auto it = certainty_.find(storage_index);
  return it == certainty_.end() ? 0 : it->second.abandoned_ticks;
}

int AnchorHistory::contradictedBinsAt(const ReflectanceField& field, int storage_index) const {
  if (field.missedBinsAt(storage_index) == 0) return 0;  // nothing seen through it
  const auto it = departure_.find(storage_index);
  if (it == departure_.end()) return 0;
  const int confidently_missed = field.confidentMissValue();
  int count = 0;
  forEachMaskBit(it->second.bins.data(), mask_words_, [&](int bin) {
    count += field.valueAt(storage_index, bin) <= confidently_missed;
  });
  return count;
}

size_t AnchorHistory::bytes() const {
  // Per entry: the mask words, the history and key, a hash node and its bucket pointer.
  const size_t entry = mask_words_ * sizeof(uint64_t) + sizeof(DepartureHistory) + sizeof(int) +
                       2 * sizeof(void*) + sizeof(void*);
  const size_t certainty_entry = mask_words_ * sizeof(uint64_t) + theta_bins_ * sizeof(int8_t) +
                                 sizeof(CertaintyHistory) + sizeof(int) + 3 * sizeof(void*);
  return confirmed_ticks_.size() + arrival_.size() + departure_.size() * entry +
         certainty_.size() * certainty_entry;
}

void AnchorHistory::clear() {
  departure_.clear();
  certainty_.clear();
  confirmed_ticks_.zeroWhereSet();
  arrival_.zeroWhereSet();
}

void AnchorHistory::forgetTiles(const std::vector<TileIndex>& tiles, const RollingWindow& window) {
  const int tile_slots = window.tileCells() * window.tileCells();
  for (const TileIndex& tile : tiles) {
    const int first = window.tileFirstSlot(tile);
    std::fill_n(&confirmed_ticks_[first], tile_slots, uint8_t{0});
    std::fill_n(&arrival_[first], tile_slots, uint8_t{0});
    if (departure_.empty() && certainty_.empty()) continue;
    for (int slot = first; slot < first + tile_slots; ++slot) {
      departure_.erase(slot);
      certainty_.erase(slot);
    }
  }
}

void AnchorHistory::tick(ReflectanceField& field, const AnchorRules& rules, ParallelRunner* runner,
                         int scans) {
  // On the runner's threads: they split the histories by hash bucket and the cells by tile, and
  // each updates only what it was given. Histories to drop or create change the maps, so the
  // threads collect those and the caller makes them after each step.
  const int threads = runner ? runner->threads() : 1;
  // Per thread: slots of histories to drop, of cells to get a history, of cells to become certain.
  std::vector<std::vector<int>> dropped(threads), remembered(threads), certain(threads);
  auto for_each_history = [&](auto& histories, auto&& update) {
    constexpr size_t kBucketsPerPart = 256;
    const size_t buckets = histories.bucket_count();
    parallelFor(runner, (buckets + kBucketsPerPart - 1) / kBucketsPerPart, 1,
                [&](size_t part, int thread) {
                  const size_t end = std::min(buckets, (part + 1) * kBucketsPerPart);
                  for (size_t b = part * kBucketsPerPart; b < end; ++b) {
                    for (auto it = histories.begin(b); it != histories.end(b); ++it)
                      update(it->first, it->second, thread);
                  }
                });
  };
  // Abandonment first, like vacancy: it compares with the last tick and reads the hits since.
  for_each_history(certainty_, [&](int slot, CertaintyHistory& history, int thread) {
    if (!field.reflectiveBinsAt(slot)) {
      dropped[thread].push_back(slot);  // no longer confirmed
      return;
    }
    bool lost_certainty = false;
    forEachMaskBit(history.certain.data(), mask_words_, [&](int bin) {
      const int8_t value = field.valueAt(slot, bin);
      lost_certainty |= value < history.at_tick[bin];
      history.at_tick[bin] = value;
    });
    if (field.hitSinceTick(slot)) {
      history.abandoned_ticks = 0;
    } else if (lost_certainty && history.abandoned_ticks < 255) {
      ++history.abandoned_ticks;
    }
  });
  for (const std::vector<int>& part : dropped) {
    for (int slot : part)
      certainty_.erase(slot);
  }
  // Vacancy first: it reads the hits since the last tick, which the loop below clears.
  for_each_history(departure_, [&](int slot, DepartureHistory& history, int) {
    const int missed = field.missedBinsAt(slot);
    const bool seen_anew = missed > history.missed_at_tick;
    if (field.hitSinceTick(slot) || (seen_anew && hitNear(field, slot, rules.vacancy_hit_radius))) {
      history.vacant_ticks = 0;
      history.vacant_scans = 0;
    } else if (seen_anew) {
      history.vacant_ticks = static_cast<uint8_t>(std::min(255, history.vacant_ticks + 1));
      history.vacant_scans = static_cast<uint8_t>(std::min(255, history.vacant_scans + scans));
    }
    history.missed_at_tick = static_cast<uint16_t>(missed);
  });
  // Tile by tile: storage tiles are contiguous blocks of slots.
  const RollingWindow& window = field.window();
  const size_t tile_slots = size_t{1} << window.tileSlotShift();
  constexpr size_t kTilesPerPart = 16;
  const size_t tiles = window.storageTiles();
  const size_t plane = tiles * tile_slots;
  const int remembered_min_bins = rules.remembered_min_bins;
  const int confirmed_min_ticks = rules.confirmed_min_ticks;
  parallelFor(runner, (tiles + kTilesPerPart - 1) / kTilesPerPart, 1, [&](size_t part, int thread) {
    const size_t end = std::min(plane, (part + 1) * kTilesPerPart * tile_slots);
    for (size_t first = part * kTilesPerPart * tile_slots; first < end; first += tile_slots) {
      const int storage_tile = static_cast<int>(first >> window.tileSlotShift());
      // A tile with no hit and no mask change since the last tick was left as this tick would
      // leave it: hit flags clear, unreflective cells at 0 ticks, reflective ones held, histories
      // holding their masks. Unless every cell is remembered, reflective or not (min bins 0).
      // A bin becoming confidently missed marks its tile too: its cell may be seen free now.
      if (!field.takeTickPending(storage_tile) && remembered_min_bins > 0) continue;
      if (remembered_min_bins > 0 && field.tileReflectiveCells(storage_tile) == 0) {
        // No cell of this tile is reflective: none is remembered or confirmed, so all that is
        // left to do is what the loop below does to unreflective cells.
        std::fill_n(&confirmed_ticks_[first], tile_slots, uint8_t{0});
        for (size_t index = first; index < first + tile_slots; ++index)
          arrival_[index] = seenFree(field, static_cast<int>(index), arrival_[index],
                                     rules.wide_arrival_min_missed_bins);
        field.clearSinceTick(static_cast<int>(first), static_cast<int>(tile_slots));
        continue;
      }
      for (size_t index = first; index < first + tile_slots; ++index) {
        const int slot = static_cast<int>(index);
        const int reflective = field.reflectiveBinsAt(slot);
        const bool hit = field.hitSinceTick(slot);
        if (reflective >= remembered_min_bins) {
          const auto it = departure_.find(slot);
          if (it != departure_.end()) {
            addReflectiveBins(field, index, rules.wide_min_bins, it->second);
          } else {
            remembered[thread].push_back(slot);
          }
        }
        // Reflective now after being seen free at the last tick: something arrived there.
        uint8_t& arrival = arrival_[index];
        if (!reflective) {
          arrival = seenFree(field, slot, arrival, rules.wide_arrival_min_missed_bins);
        } else {
          arrival = arrive(arrival);
        }
        uint8_t& ticks = confirmed_ticks_[index];
        if (!reflective) {
          ticks = 0;
        } else if (hit && ticks < 255) {
          ++ticks;  // not hit (occluded, out of view): held, neither confirmed nor reset
        }
        // Only hits make a bin certain.
        if (confirmed_min_ticks > 0 && ticks >= confirmed_min_ticks && hit) {
          const auto it = certainty_.find(slot);
          if (it != certainty_.end()) {
            addCertainBins(field, index, it->second);
          } else {
            certain[thread].push_back(slot);
          }
        }
      }
      field.clearSinceTick(static_cast<int>(first), static_cast<int>(tile_slots));
    }
  });
  for (const std::vector<int>& part : remembered) {
    for (int slot : part) {
      DepartureHistory& history = departure_[slot];
      history.missed_at_tick = static_cast<uint16_t>(field.missedBinsAt(slot));
      addReflectiveBins(field, slot, rules.wide_min_bins, history);
    }
  }
  for (const std::vector<int>& part : certain) {
    for (int slot : part) {
      CertaintyHistory& history = certainty_[slot];
      history.certain.assign(mask_words_, 0);
      history.at_tick.resize(theta_bins_);
      addCertainBins(field, slot, history);
    }
  }
}

void AnchorHistory::addReflectiveBins(const ReflectanceField& field, size_t storage_index,
                                      int wide_min_bins, DepartureHistory& history) const {
  history.wide |= field.reflectiveBinsAt(static_cast<int>(storage_index)) >= wide_min_bins;
  history.bins.resize(mask_words_, 0);
  const uint64_t* mask = field.reflectiveMaskAt(static_cast<int>(storage_index));
  for (int w = 0; w < mask_words_; ++w)
    history.bins[w] |= mask[w];
}

void AnchorHistory::addCertainBins(const ReflectanceField& field, size_t storage_index,
                                   CertaintyHistory& history) const {
  // Certain bins are reflective ones at the clamp.
  const int slot = static_cast<int>(storage_index);
  forEachMaskBit(field.reflectiveMaskAt(slot), mask_words_, [&](int bin) {
    const int8_t value = field.valueAt(slot, bin);
    if (value < field.logOdds().maxValue()) return;
    history.certain[bin >> 6] |= uint64_t{1} << (bin & 63);
    history.at_tick[bin] = value;
  });
}

}  // namespace rfm
