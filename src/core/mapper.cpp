#include "reflectance_field_map/core/mapper.h"

#include "reflectance_field_map/core/clearance_map.h"
#include "reflectance_field_map/core/frozen_reflectivity.h"
#include "reflectance_field_map/core/glass_completion.h"
#include "reflectance_field_map/core/motion_removal.h"
#include "reflectance_field_map/core/occupancy.h"
#include "reflectance_field_map/core/ray_classification.h"
#include "reflectance_field_map/core/ray_insertion.h"
#include "reflectance_field_map/core/scan_inserter.h"
#include "reflectance_field_map/core/shared_leap.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>

namespace rfm {
namespace {

constexpr uint32_t kMapperMagic = 0x52464d53;  // "RFMS"

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Metres along a ray (unit `direction`) per cell along its major axis. No cell within Chebyshev
// distance c of a cell blocks: then neither does the ray's stretch of c of these from any point
// of that cell, which on a diagonal is 1.41 cells long.
double leapPerCell(const Eigen::Vector2d& direction, double resolution) {
  return resolution / direction.cwiseAbs().maxCoeff();
}

}  // namespace

// A scan as inserted, kept for online re-processing when new glass appears.
struct BufferedScan {
  std::vector<Ray> rays;    // after clipping to the window and truncation at known glass
  Eigen::Vector2d origin;   // of every ray (the sensor, inside the window)
  double first_beam_angle;  // world direction of beam 0, rad
  double increment;         // rad between beams
};

struct Mapper::Impl {
  Impl(const MapperOptions& options, const ReflectanceField& field)
      : rule(options.occupancy, field.geometry().binWidth()),
        remover(rule, AnchorRules::fromOptions(options.motion_removal, field.geometry(), rule,
                                               field.logOdds())),
        anchor_history(field),
        runner(std::make_shared<ParallelRunner>(options.insertion.insertion_threads)),
        inserter(runner),
        classes(static_cast<size_t>(field.window().sizeCells()) * field.window().sizeCells(),
                CellClass::kUnknown),
        clearance(options.reflection_removal.clearance_block_shift),
        completion(field.geometry(), options.reflection_removal.reflection_removal_enabled
                                         ? options.reflection_removal.glass_completion_max_gap
                                         : 0.0) {}

  OccupancyRule rule;
  MotionRemover remover;
  AnchorHistory anchor_history;
  // The mapper's threads (insertion_threads), for one job at a time: insertion (by theta bin),
  // re-centring (by tile), the reflection check (by ray), motion removal (by band of rows) and
  // batch labelling (by scan).
  std::shared_ptr<ParallelRunner> runner;
  ScanInserter inserter;
  // Classes of the active window from the last motion removal, by storage index.
  std::vector<CellClass> classes;
  size_t blocking_cells = 0;     // glass/metal/static cells in `classes`
  ClearanceMap clearance;        // of `classes`: distance to the nearest cell blocking rays
  double last_tick_stamp = 0.0;  // persistence ticks follow the scans' clock
  std::deque<BufferedScan> buffer;
  std::vector<Ray> rays;
  std::vector<std::vector<Ray>> pending;  // addScans: prepared, not yet inserted
  std::vector<CellClass> box_classes;
  std::vector<CellClass> entering_classes;  // placeScan: a tile's classes from the global map
  MapperStats stats;
  FrozenReflectivity frozen;  // set by restartEvidence until the next removeMotion
  GlassCompletion completion;
  // Tiles holding cells completed as glass at the last motion removal: their classes changed
  // without their evidence changing, so motion removal's reuse of unchanged tiles skips them.
  std::vector<TileIndex> completed_tiles;
  std::vector<uint8_t> completed_storage_tiles;  // scratch: those and this run's, by storage tile
  std::optional<Eigen::Vector2d> held_centre;    // holdActiveRegionAt
};

Mapper::Mapper(const MapperOptions& options)
    : options_((options.validate(), options)),
      field_(options.grid, options.log_odds, options.active_region),
      map_(),
      impl_(std::make_unique<Impl>(options, field_)) {}

Mapper::~Mapper() = default;

const AnchorHistory& Mapper::anchorHistory() const {
  return impl_->anchor_history;
}

CellClass Mapper::cellClass(const CellIndex& cell) const {
  if (field_.inActiveRegion(cell)) return impl_->classes[field_.window().storageIndex(cell)];
  return map_.get(cell);
}

ScanUpdate Mapper::addScan(const TimedScan& scan) {
  ScanUpdate update = placeScan(scan);
  if (!update.error.empty()) return update;
  makeRays(scan, impl_->rays, update);
  const auto cut_start = std::chrono::steady_clock::now();
  impl_->stats.reflection_rays += cutAtGlass(impl_->rays, update, impl_->runner.get());
  update.reflection_ms = millisecondsSince(cut_start);
  const auto insert_start = std::chrono::steady_clock::now();
  update.bin_updates = impl_->inserter.insert(impl_->rays, field_);
  update.insert_ms = millisecondsSince(insert_start);
  finishScan(scan, impl_->rays, update);
  return update;
}

void Mapper::addScans(ScanIterator first, ScanIterator last) {
  std::vector<const TimedScan*> scans;
  scans.reserve(last - first);
  for (ScanIterator scan = first; scan != last; ++scan)
    scans.push_back(&*scan);
  addScans(scans);
}

void Mapper::addScans(const std::vector<const TimedScan*>& scans) {
  if (checksGlass() && !impl_->frozen.active()) {
    // The glass check reads the field as the scans before left it: one by one.
    for (const TimedScan* scan : scans)
      addScan(*scan);
    return;
  }
  // Scans go into the field together until the window moves or a persistence tick is due
  // (ticks read the field as the scans before them left it). A glass check against frozen
  // reflectivity reads nothing the group changes, so a group's scans make and cut their rays
  // side by side, one scan per thread, and then go in theta bin by theta bin.
  std::vector<const TimedScan*> group;
  std::vector<std::vector<Ray>>& rays = impl_->pending;
  auto flush = [&] {
    if (rays.size() < group.size()) rays.resize(group.size());
    std::vector<size_t> cut(group.size(), 0);
    parallelFor(impl_->runner.get(), group.size(), 1, [&](size_t i, int) {
      ScanUpdate update;
      update.labels.assign(group[i]->scan.ranges.size(), RayLabel::kNoReturn);
      makeRays(*group[i], rays[i], update);
      cut[i] = cutAtGlass(rays[i], update, /*runner=*/nullptr);
    });
    impl_->inserter.insertScans(rays, group.size(), field_);
    for (size_t i = 0; i < group.size(); ++i) {
      impl_->stats.reflection_rays += cut[i];
      keepInsertedRays(*group[i], rays[i]);
    }
    group.clear();
  };
  for (const TimedScan* scan : scans) {
    if (!group.empty() && field_.wouldRecenter(regionCentre(*scan))) flush();
    if (!placeScan(*scan).error.empty()) continue;
    group.push_back(scan);
    if (tickDue(scan->stamp)) flush();
    countScan(scan->stamp);
  }
  if (!group.empty()) flush();
}

void Mapper::holdActiveRegionAt(const Eigen::Vector2d& centre) {
  impl_->held_centre = centre;
}

const Eigen::Vector2d& Mapper::regionCentre(const TimedScan& scan) const {
  return impl_->held_centre ? *impl_->held_centre : scan.robot_pose.position;
}

ScanUpdate Mapper::placeScan(const TimedScan& scan) {
  ScanUpdate update;
  update.labels.assign(scan.scan.ranges.size(), RayLabel::kNoReturn);
  update.error = scan.scan.validate();
  if (!update.error.empty()) return update;

  const WindowShift shift = field_.recenter(regionCentre(scan), impl_->runner.get());
  update.region_moved = shift.moved;
  if (shift.moved) {
    impl_->anchor_history.forgetTiles(shift.left, field_.window());
    // Entering cells take the classes the global map remembers for them: a tile at a time (a
    // batch's window enters whole, every pass).
    std::vector<CellClass>& remembered = impl_->entering_classes;
    for (const TileIndex& tile : shift.entered) {
      const CellBox box = field_.window().tileBox(tile);
      map_.extract(box, remembered);
      size_t i = 0;
      for (int y = box.min.y(); y < box.max.y(); ++y) {
        for (int x = box.min.x(); x < box.max.x(); ++x)
          impl_->classes[field_.window().storageIndex({x, y})] = remembered[i++];
      }
    }
    if (!impl_->buffer.empty()) impl_->buffer.clear();  // rays refer to the old window
    updateClearance();
  }
  return update;
}

void Mapper::makeRays(const TimedScan& scan, std::vector<Ray>& rays, ScanUpdate& update) const {
  scanToRays(scan.scan, scan.sensor_pose, options_.insertion, rays);
  for (const Ray& ray : rays)
    update.labels[ray.beam] = RayLabel::kKept;
  clipToActiveRegion(rays);
}

bool Mapper::checksGlass() const {
  return options_.reflection_removal.reflection_removal_enabled && impl_->blocking_cells > 0;
}

size_t Mapper::cutAtGlass(std::vector<Ray>& rays, ScanUpdate& update,
                          ParallelRunner* runner) const {
  if (!checksGlass()) return 0;
  // Read-only on the field and the classes: the rays split between threads freely.
  constexpr size_t kChunk = 64;
  parallelFor(runner, (rays.size() + kChunk - 1) / kChunk, 1, [&](size_t chunk, int) {
    const size_t first = chunk * kChunk, count = std::min(kChunk, rays.size() - first);
    double distances[kChunk];
    passThroughDistances(&rays[first], count, distances);
    for (size_t i = first; i < first + count; ++i) {
      const bool returned = rays[i].hit;  // only a return can be a reflection
      if (cutAtDistance(distances[i - first], rays[i]) && returned) {
        update.labels[rays[i].beam] = RayLabel::kReflection;
      }
    }
  });
  return std::count(update.labels.begin(), update.labels.end(), RayLabel::kReflection);
}

void Mapper::countScan(double stamp) {
  tickPersistenceIfDue(stamp);
  ++impl_->stats.scans_processed;
}

void Mapper::keepInsertedRays(const TimedScan& scan, const std::vector<Ray>& rays) {
  impl_->stats.rays_inserted += rays.size();
  if (options_.reflection_removal.scan_buffer_size == 0) return;
  impl_->buffer.push_back({rays, scan.sensor_pose.position,
                           scan.sensor_pose.yaw + scan.scan.angle_min,
                           static_cast<double>(scan.scan.angle_increment)});
  while (impl_->buffer.size() > static_cast<size_t>(options_.reflection_removal.scan_buffer_size))
    impl_->buffer.pop_front();
}

void Mapper::finishScan(const TimedScan& scan, const std::vector<Ray>& rays,
                        const ScanUpdate& update) {
  countScan(scan.stamp);
  keepInsertedRays(scan, rays);
  impl_->stats.last_insert_ms = update.insert_ms;
  impl_->stats.last_reflection_ms = update.reflection_ms;
}

bool Mapper::tickDue(double stamp) const {
  return impl_->stats.scans_processed > 0 && stamp >= impl_->last_tick_stamp &&
         stamp - impl_->last_tick_stamp >= 1.0 / options_.motion_removal.motion_removal_rate;
}

void Mapper::tickPersistenceIfDue(double stamp) {
  if (tickDue(stamp)) {
    impl_->anchor_history.tick(field_, impl_->remover.anchors(), impl_->runner.get());
    impl_->last_tick_stamp = stamp;
  } else if (impl_->stats.scans_processed == 0 || stamp < impl_->last_tick_stamp) {
    impl_->last_tick_stamp = stamp;  // first scan, or time went back
  }
}

MotionRemovalSummary Mapper::removeMotion() {
  const auto start = std::chrono::steady_clock::now();
  impl_->frozen.clear();  // the glass check reads the field again
  MotionRemovalSummary summary;
  const CellBox box = field_.activeBox();
  std::vector<CellClass>& box_classes = impl_->box_classes;
  if (options_.motion_removal.motion_removal_enabled) {
    static_cast<MotionRemovalCounts&>(summary) = impl_->remover.classify(
        field_, impl_->anchor_history, box,
        [this](const CellIndex& cell) { return map_.get(cell); }, box_classes, impl_->runner.get());
    impl_->stats.free_cells = summary.free_cells;
  } else {
    // Plain eq. 5 projection: occupied, free or unknown.
    box_classes.resize(static_cast<size_t>(box.width()) * box.height());
    size_t i = 0, free_cells = 0, occupied = 0;
    field_.window().forEachCell(box, [&](int, int, int slot) {
      const CellClass c =
          impl_->rule.classify(field_.reflectiveBinsAt(slot), field_.missedBinsAt(slot));
      box_classes[i++] = c;
      free_cells += c == CellClass::kFree;
      occupied += c == CellClass::kOccupied;
    });
    summary.static_cells = occupied;
    impl_->stats.free_cells = free_cells;
  }

  // Glass the robot has not faced yet, on the lines of glass it has. These cells change class
  // with no change of evidence, so their tiles (and last time's) are not reused as unchanged.
  const RollingWindow& window = field_.window();
  std::vector<TileIndex> completed_tiles;
  for (int i : impl_->completion.complete(field_, box, box_classes)) {
    completed_tiles.push_back(
        window.tileOf({box.min.x() + i % box.width(), box.min.y() + i / box.width()}));
    ++summary.glass_cells;
  }
  std::vector<uint8_t>& completed_here = impl_->completed_storage_tiles;  // by storage tile
  completed_here.assign(window.storageTiles(), 0);
  for (const auto* tiles : {&completed_tiles, &impl_->completed_tiles}) {
    for (const TileIndex& tile : *tiles) {
      if (window.contains(window.tileBox(tile).min)) completed_here[window.storageTile(tile)] = 1;
    }
  }
  const bool removed_motion = options_.motion_removal.motion_removal_enabled;
  auto reused_tile = [&](const CellIndex& cell, int slot) {
    return removed_motion && impl_->remover.reusedTile(cell) &&
           !completed_here[slot >> window.tileSlotShift()];
  };

  // New glass: cells now blocking that were not before. Rows on the threads.
  struct alignas(64) RowResult {
    size_t blocking = 0;
    CellBox new_glass;
    bool blocking_changed = false;  // a cell started or stopped blocking rays
  };
  std::vector<RowResult> rows(box.height());
  parallelFor(impl_->runner.get(), rows.size(), 16, [&](size_t row, int) {
    const int y = box.min.y() + static_cast<int>(row);
    RowResult& result = rows[row];
    field_.window().forEachTileSpan(
        {{box.min.x(), y}, {box.max.x(), y + 1}}, [&](int, int x_begin, int x_end, int slot) {
          // A reused tile's cells, free or unknown, are stored already.
          if (reused_tile({x_begin, y}, slot)) return;
          size_t i = row * box.width() + (x_begin - box.min.x());
          for (int x = x_begin; x < x_end; ++x, ++slot) {
            CellClass& stored = impl_->classes[slot];
            const CellClass now = box_classes[i++];
            if (blocksRays(now)) {
              ++result.blocking;
              if (!blocksRays(stored) && now != CellClass::kStatic) {
                result.new_glass = result.new_glass.unite({{x, y}, {x + 1, y + 1}});
              }
            }
            result.blocking_changed |= blocksRays(stored) != blocksRays(now);
            stored = now;
          }
        });
  });
  CellBox new_glass;
  bool blocking_changed = false;
  impl_->blocking_cells = 0;
  for (const RowResult& result : rows) {
    impl_->blocking_cells += result.blocking;
    new_glass = new_glass.unite(result.new_glass);
    blocking_changed |= result.blocking_changed;
  }
  const CellBox& clearance_box = impl_->clearance.box();
  if (blocking_changed || clearance_box.min != box.min || clearance_box.max != box.max) {
    impl_->clearance.compute(box, [&](int dx, int dy) {
      return !blocksRays(box_classes[static_cast<size_t>(dy) * box.width() + dx]);
    });
  }
  auto box_class = [&](const CellIndex& cell) {
    return box_classes[static_cast<size_t>(cell.y() - box.min.y()) * box.width() +
                       (cell.x() - box.min.x())];
  };
  if (!removed_motion) {
    map_.assign(box, box_class);
  } else {
    // Reused tiles hold what the map got last time.
    for (const TileIndex& tile : window.tiles()) {
      const CellBox tile_box = window.tileBox(tile);
      if (!reused_tile(tile_box.min, window.tileFirstSlot(tile))) map_.assign(tile_box, box_class);
    }
  }
  impl_->completed_tiles = std::move(completed_tiles);
  summary.new_glass = !new_glass.empty();
  if (summary.new_glass && options_.reflection_removal.reflection_removal_enabled) {
    revertEvidenceBehindGlass(new_glass);
  }
  summary.elapsed_ms = millisecondsSince(start);
  impl_->stats.last_motion_removal_ms = summary.elapsed_ms;
  impl_->stats.occupied_cells = summary.static_cells + summary.glass_cells + summary.metal_cells;
  impl_->stats.glass_cells = summary.glass_cells + summary.metal_cells;
  impl_->stats.motion_cells = summary.motion_cells;
  return summary;
}

void Mapper::revertEvidenceBehindGlass(const CellBox& new_glass) {
  // Online Alg. 3: buffered scans whose rays pass through glass found since they were inserted
  // added evidence beyond it. Replay each such scan's de-duplicated updates with and without
  // that evidence and apply the difference (reverts stop at the prior, see revertHitAt).
  // De-duplication is per theta bin, so only the bins holding a changed ray are replayed, and
  // only rays crossing the new glass can change.
  const GridGeometry& geometry = field_.geometry();
  const double resolution = geometry.resolution();
  std::vector<BinUpdate> before, after;
  std::vector<Ray> old_rays, new_rays;
  std::vector<std::pair<size_t, Ray>> truncated;  // index in the scan, ray cut at the glass
  std::vector<uint8_t> bin_changed(geometry.thetaBins());
  std::vector<BeamRange> beam_ranges;
  auto by_beam = [](const Ray& ray, uint32_t beam) { return ray.beam < beam; };
  for (BufferedScan& buffered : impl_->buffer) {
    truncated.clear();
    // Rays are in beam order: only those heading towards the new glass are looked at.
    beamsTowardsBox(new_glass, resolution, buffered.origin, buffered.first_beam_angle,
                    buffered.increment, beam_ranges);
    for (const BeamRange& range : beam_ranges) {
      auto it = std::lower_bound(buffered.rays.begin(), buffered.rays.end(), range.first, by_beam);
      for (; it != buffered.rays.end() && it->beam <= range.last; ++it) {
        Ray ray = *it;
        if (!clipRayToBox(new_glass, resolution, ray)) continue;  // misses the new glass
        ray = *it;
        if (truncateAtGlass(ray)) truncated.emplace_back(it - buffered.rays.begin(), ray);
      }
    }
    if (truncated.empty()) continue;  // in beam order: the ranges ascend and are disjoint
    std::fill(bin_changed.begin(), bin_changed.end(), 0);
    for (const auto& changed : truncated)
      bin_changed[geometry.binOf(changed.second.angle)] = 1;
    old_rays.clear();
    new_rays.clear();
    auto next_truncated = truncated.begin();
    for (size_t k = 0; k < buffered.rays.size(); ++k) {
      const bool cut = next_truncated != truncated.end() && next_truncated->first == k;
      const Ray& now = cut ? (next_truncated++)->second : buffered.rays[k];
      if (!bin_changed[geometry.binOf(now.angle)]) continue;
      old_rays.push_back(buffered.rays[k]);
      new_rays.push_back(now);
    }
    impl_->inserter.collectUpdates(old_rays, field_, before);
    impl_->inserter.collectUpdates(new_rays, field_, after);
    size_t i = 0, j = 0;
    while (i < before.size() || j < after.size()) {
      if (j == after.size() || (i < before.size() && before[i] < after[j])) {
        undo(before[i++]);
      } else if (i == before.size() || after[j] < before[i]) {
        redo(after[j++]);
      } else {
        if (before[i].hit != after[j].hit) {
          undo(before[i]);
          redo(after[j]);
        }
        ++i;
        ++j;
      }
    }
    for (const auto& changed : truncated)
      buffered.rays[changed.first] = changed.second;
  }
}

void Mapper::updateClearance() {
  const CellBox box = field_.activeBox();
  impl_->clearance.compute(box, [&](int dx, int dy) {
    return !blocksRays(impl_->classes[field_.window().storageIndex(box.min + CellIndex(dx, dy))]);
  });
}

void Mapper::undo(const BinUpdate& update) {
  if (update.hit) {
    field_.revertHitAt(update.slot, update.bin);
  } else {
    field_.revertMissAt(update.slot, update.bin);
  }
}

void Mapper::redo(const BinUpdate& update) {
  if (update.hit) {
    field_.applyHitAt(update.slot, update.bin);
  } else {
    field_.applyMissAt(update.slot, update.bin);
  }
}

std::vector<RayLabel> Mapper::labelScan(const TimedScan& scan, bool final_map) const {
  std::vector<RayLabel> labels(scan.scan.ranges.size(), RayLabel::kNoReturn);
  if (!scan.scan.validate().empty()) return labels;
  std::vector<Ray> rays;
  scanToRays(scan.scan, scan.sensor_pose, options_.insertion, rays);
  auto class_of = [this](const CellIndex& cell) { return cellClass(cell); };
  const bool check_reflections =
      options_.reflection_removal.reflection_removal_enabled && impl_->blocking_cells > 0;
  // The reflection check of every hit ray first, side by side (passThroughDistances).
  std::vector<Ray> checked;
  std::vector<double> through;
  if (check_reflections) {
    const CellBox box = field_.activeBox();
    checked.reserve(rays.size());  // grown one by one, it reallocated ten times a scan
    for (const Ray& ray : rays) {
      Ray inside = ray;
      if (ray.hit && clipRayToBox(box, field_.geometry().resolution(), inside)) {
        checked.push_back(inside);
      }
    }
    through.resize(checked.size());
    passThroughDistances(checked.data(), checked.size(), through.data());
  }
  size_t next_checked = 0;
  for (const Ray& ray : rays) {
    if (!ray.hit) continue;  // no return: nothing to keep or remove
    if (next_checked < checked.size() && checked[next_checked].beam == ray.beam &&
        through[next_checked++] >= 0.0) {
      labels[ray.beam] = RayLabel::kReflection;
      continue;
    }
    labels[ray.beam] = labelEndpoint(
        ray, field_.geometry(), options_.active_region.active_region_radius, final_map, class_of);
  }
  return labels;
}

std::vector<RayLabel> Mapper::labelAddedScan(const TimedScan& scan,
                                             const ScanUpdate& update) const {
  std::vector<RayLabel> labels = labelScan(scan);
  for (size_t i = 0; i < labels.size() && i < update.labels.size(); ++i) {
    if (update.labels[i] == RayLabel::kReflection) labels[i] = RayLabel::kReflection;
  }
  return labels;
}

std::vector<std::vector<RayLabel>> Mapper::labelScans(ScanIterator first, ScanIterator last,
                                                      bool final_map) const {
  std::vector<std::vector<RayLabel>> labels(last - first);
  parallelFor(impl_->runner.get(), labels.size(), 1,
              [&](size_t i, int) { labels[i] = labelScan(first[i], final_map); });
  return labels;
}

void Mapper::clipToActiveRegion(std::vector<Ray>& rays) const {
  const CellBox box = field_.activeBox();
  const double resolution = field_.geometry().resolution();
  const double radius = options_.active_region.active_region_radius;
  size_t kept = 0;
  for (Ray& ray : rays) {
    // Evidence only within the active-region radius of the sensor, live and in batch alike.
    clipRayToLength(radius, ray);
    if (clipRayToBox(box, resolution, ray)) rays[kept++] = ray;
  }
  rays.resize(kept);
}

double Mapper::passThroughDistance(const Ray& ray) const {
  double distance = -1.0;
  passThroughDistances(&ray, 1, &distance);
  return distance;
}

void Mapper::passThroughDistances(const Ray* rays, size_t count, double* distances) const {
  const GridGeometry& geometry = field_.geometry();
  const double resolution = geometry.resolution();
  const double tolerance = options_.reflection_removal.penetration_tolerance;
  const ClearanceMap& clearance = impl_->clearance;
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
      const PassThroughDetector& detector = detectors[i].emplace(block[i], geometry, tolerance);
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

double Mapper::walkTowardsGlass(const Ray& ray, PassThroughDetector& detector, double from,
                                double leap_unit) const {
  const Eigen::Vector2d& direction = detector.direction();
  const double stop = detector.lastCandidate();
  const Eigen::Vector2d last = ray.origin + direction * stop;
  const GridGeometry& geometry = field_.geometry();
  const double resolution = geometry.resolution();
  const int bins = geometry.thetaBins();
  const ClearanceMap& clearance = impl_->clearance;
  const FrozenReflectivity& frozen = impl_->frozen;
  auto class_of = [this](const CellIndex& cell) { return cellClass(cell); };
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
          const CellClass c = impl_->classes[slot];
          auto reflective_near = [&](int bin) {
            return reflectiveNear(
                frozen.active() ? frozen.maskOf({x, y}) : field_.reflectiveMaskAt(slot), bin, bins);
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

bool Mapper::truncateAtGlass(Ray& ray) const {
  return cutAtDistance(passThroughDistance(ray), ray);
}

bool Mapper::cutAtDistance(double along, Ray& ray) const {
  if (along < 0.0) return false;
  // Evidence beyond the surface is discarded (Alg. 3): misses up to it, no hit. Even the misses
  // beyond glass are dropped: a mirror looks like glass in the field, and beyond a mirror the
  // path is folded, so its misses would erase real walls.
  const Eigen::Vector2d direction = (ray.end - ray.origin).normalized();
  ray.end = ray.origin + direction * (along + 0.5 * field_.geometry().resolution());
  ray.hit = false;
  return true;
}

void Mapper::restartEvidence() {
  impl_->frozen.freeze(field_, impl_->classes);
  // Classes live on in the global map; the next scan re-places the window and restores them.
  field_.clear();
  impl_->anchor_history.clear();
  impl_->buffer.clear();
}

void Mapper::reset() {
  impl_->frozen.clear();
  field_.clear();
  impl_->anchor_history.clear();
  map_.clear();
  std::fill(impl_->classes.begin(), impl_->classes.end(), CellClass::kUnknown);
  impl_->blocking_cells = 0;
  impl_->clearance.clear();
  impl_->buffer.clear();
  impl_->completed_tiles.clear();
  impl_->stats = MapperStats();
}

void Mapper::save(std::ostream& out) const {
  const uint32_t magic = kMapperMagic;
  out.write(reinterpret_cast<const char*>(&magic), sizeof(magic));
  map_.write(out);
  field_.write(out);
}

bool Mapper::load(std::istream& in) {
  uint32_t magic = 0;
  if (!in.read(reinterpret_cast<char*>(&magic), sizeof(magic)) || magic != kMapperMagic) {
    return false;
  }
  GlobalMap2D map;
  if (!map.read(in)) return false;
  if (!field_.read(in)) return false;  // leaves the field untouched on failure
  map_ = std::move(map);
  impl_->anchor_history.clear();
  // The window is placed afresh by the next scan; its classes then come from the loaded map.
  std::fill(impl_->classes.begin(), impl_->classes.end(), CellClass::kUnknown);
  impl_->blocking_cells = 0;
  impl_->clearance.clear();
  impl_->buffer.clear();
  impl_->completed_tiles.clear();
  impl_->frozen.clear();
  return true;
}

MapperStats Mapper::stats() const {
  MapperStats stats = impl_->stats;
  // The active region: the field and the mapper's per-cell classes.
  stats.field_bytes = field_.activeBytes() + impl_->anchor_history.bytes() +
                      impl_->classes.size() * sizeof(CellClass);
  stats.archived_bytes = field_.archivedBytes();
  return stats;
}

}  // namespace rfm
