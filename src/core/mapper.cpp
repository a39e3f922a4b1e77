#include "reflectance_field_map/core/mapper.h"

#include "reflectance_field_map/core/active_classes.h"
#include "reflectance_field_map/core/anchor_history.h"
#include "reflectance_field_map/core/occupancy.h"
#include "reflectance_field_map/core/ray_labels.h"
#include "reflectance_field_map/core/reflection_removal.h"
#include "reflectance_field_map/core/region_classifier.h"
#include "reflectance_field_map/core/scan_inserter.h"

#include <chrono>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <utility>

namespace rfm {
namespace {

constexpr uint32_t kMapperMagic = 0x52464d53;  // "RFMS"

void validate(const MapperLayout& layout) {
  if (!(layout.window_radius >= 0.0 && layout.window_radius <= MapperLayout::kMaxWindowRadius)) {
    throw InvalidOption("window_radius", std::to_string(layout.window_radius),
                        "[0, " + std::to_string(MapperLayout::kMaxWindowRadius) + "]");
  }
  if (layout.clearance_block_shift < 0 ||
      layout.clearance_block_shift > ClearanceMap::kMaxBlockShift) {
    throw InvalidOption("clearance_block_shift", std::to_string(layout.clearance_block_shift),
                        "[0, " + std::to_string(ClearanceMap::kMaxBlockShift) + "]");
  }
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

// The steps, and what they keep between scans.
struct Mapper::Impl {
  Impl(const MapperOptions& options, const MapperLayout& layout, const ReflectanceField& field,
       const GlobalMap2D& map)
      : runner(std::make_shared<ParallelRunner>(options.insertion.insertion_threads)),
        inserter(runner),
        rule(options.occupancy, field.geometry().binWidth()),
        motion(rule, AnchorRules::fromOptions(options.motion_removal, field.geometry(), rule,
                                              field.logOdds())),
        anchor_history(field),
        classifier(rule, options.motion_removal.motion_removal_enabled ? &motion : nullptr,
                   GlassCompletion(field.geometry(),
                                   options.reflection_removal.reflection_removal_enabled
                                       ? options.reflection_removal.glass_completion_max_gap
                                       : 0.0)),
        classes(field.window(), map, layout.clearance_block_shift),
        reflections(options.reflection_removal, field, classes) {}

  // The mapper's threads (insertion_threads), for one job at a time: insertion (by theta bin),
  // re-centring (by tile), the reflection check (by ray), motion removal (by band of rows) and
  // batch labelling (by scan).
  std::shared_ptr<ParallelRunner> runner;
  ScanInserter inserter;          // Alg. 1
  OccupancyRule rule;             // eq. 5 and 7
  MotionRemover motion;           // Alg. 2
  AnchorHistory anchor_history;   // what Alg. 2's anchor rules remember
  RegionClassifier classifier;    // Alg. 2 over the region, then glass completion
  ActiveClasses classes;          // the active region's classes, from the last removal
  ReflectionRemover reflections;  // Alg. 3
  MapperStats stats;
  double last_tick_stamp = 0.0;  // persistence ticks follow the scans' clock
  bool tick_due = false;         // the last scan made a tick due; runDueTick runs it
  int scans_since_tick = 0;      // counted by countScan, handed to the tick
  std::optional<Eigen::Vector2d> held_centre;
  std::vector<Ray> rays;
  std::vector<std::vector<Ray>> pending;                 // addScans: prepared, not yet inserted
  std::chrono::steady_clock::time_point last_scan_done;  // addScan's last return
  // Where the last scans put the region's centre: revertPartBehindNewGlass looks ahead from it.
  std::optional<Eigen::Vector2d> last_centre;
  Eigen::Vector2d last_step = Eigen::Vector2d::Zero();
  // Where labelAddedScan judged arrivals since the classes last changed.
  mutable ArrivalMarks arrivals;
};

Mapper::Mapper(const MapperOptions& options, const MapperLayout& layout)
    : options_((options.validate(), validate(layout), options)),
      field_(options.grid, options.log_odds, options.active_region, layout.window_radius),
      map_(),
      impl_(std::make_unique<Impl>(options, layout, field_, map_)) {}

Mapper::~Mapper() = default;

const AnchorHistory& Mapper::anchorHistory() const {
  return impl_->anchor_history;
}

CellClass Mapper::cellClass(const CellIndex& cell) const {
  return impl_->classes.at(cell);
}

ScanUpdate Mapper::addScan(const TimedScan& scan) {
  // A scan that follows the last one within the helpers' spin (a batch, a fast replay) shares
  // its check and insertion with them. A live scan comes milliseconds after the last and finds
  // them asleep: waking them costs more CPU than the share of the scan they would take, so it
  // runs on the caller alone.
  const bool share =
      std::chrono::steady_clock::now() - impl_->last_scan_done < ParallelRunner::kSpinTime;
  ScanUpdate update = addScanSharing(scan, share);
  impl_->last_scan_done = std::chrono::steady_clock::now();
  return update;
}

ScanUpdate Mapper::addScanSharing(const TimedScan& scan, bool share) {
  // The kept scans refer to the window: a revert still pending when it moves runs first.
  if (revertPending() && field_.wouldRecenter(regionCentre(scan))) revertBehindNewGlass();
  runDueTick();
  ScanUpdate update = placeScan(scan);
  if (!update.error.empty()) return update;
  const Eigen::Vector2d& centre = regionCentre(scan);
  impl_->last_step =
      impl_->last_centre ? Eigen::Vector2d(centre - *impl_->last_centre) : Eigen::Vector2d::Zero();
  impl_->last_centre = centre;
  update.shared = share && impl_->runner->threads() > 1;
  makeRays(scan, impl_->rays, update);
  // A return still a return after the clip is the whole ray: the check below sees all of it.
  // Only a live scan's labels (labelAddedScan) read this; addScans' batch labels do not.
  update.checked_returns.assign(scan.scan.ranges.size(), 0);
  for (const Ray& ray : impl_->rays)
    if (ray.hit) update.checked_returns[ray.beam] = 1;
  const auto cut_start = std::chrono::steady_clock::now();
  impl_->stats.reflection_rays +=
      impl_->reflections.cut(impl_->rays, update.labels, share ? impl_->runner.get() : nullptr);
  update.reflection_ms = millisecondsSince(cut_start);
  const auto insert_start = std::chrono::steady_clock::now();
  update.bin_updates = impl_->inserter.insert(impl_->rays, field_, share);
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
  revertBehindNewGlass();
  runDueTick();
  if (impl_->reflections.checks() && !impl_->reflections.frozen()) {
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
      cut[i] = impl_->reflections.cut(rays[i], update.labels, /*runner=*/nullptr);
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
    runDueTick();
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
    impl_->classes.enter(shift.entered);
    impl_->reflections.forgetScans();  // their rays refer to the old window
  }
  return update;
}

void Mapper::makeRays(const TimedScan& scan, std::vector<Ray>& rays, ScanUpdate& update) const {
  scanToRays(scan.scan, scan.sensor_pose, options_.insertion, rays);
  for (const Ray& ray : rays)
    update.labels[ray.beam] = RayLabel::kKept;
  clipRaysToRegion(field_.activeBox(), field_.geometry().resolution(),
                   options_.active_region.active_region_radius, rays);
}

void Mapper::countScan(double stamp) {
  if (tickDue(stamp)) {
    impl_->tick_due = true;
    impl_->last_tick_stamp = stamp;
  } else if (impl_->stats.scans_processed == 0 || stamp < impl_->last_tick_stamp) {
    impl_->last_tick_stamp = stamp;  // first scan, or time went back
  }
  ++impl_->stats.scans_processed;
  ++impl_->scans_since_tick;
}

void Mapper::runDueTick() {
  if (!impl_->tick_due) return;
  impl_->tick_due = false;
  impl_->anchor_history.tick(field_, impl_->motion.anchors(), impl_->runner.get(),
                             impl_->scans_since_tick);
  impl_->scans_since_tick = 0;
}

bool Mapper::tickDue(double stamp) const {
  return impl_->stats.scans_processed > 0 && stamp >= impl_->last_tick_stamp &&
         stamp - impl_->last_tick_stamp >= 1.0 / options_.motion_removal.motion_removal_rate;
}

void Mapper::keepInsertedRays(const TimedScan& scan, const std::vector<Ray>& rays) {
  impl_->stats.rays_inserted += rays.size();
  impl_->reflections.keep(
      rays, scan.sensor_pose.position, scan.sensor_pose.yaw + scan.scan.angle_min,
      static_cast<double>(scan.scan.angle_increment), 0.5 * scan.scan.sweep_shift.norm());
}

void Mapper::finishScan(const TimedScan& scan, const std::vector<Ray>& rays,
                        const ScanUpdate& update) {
  countScan(scan.stamp);
  keepInsertedRays(scan, rays);
  impl_->stats.last_insert_ms = update.insert_ms;
  impl_->stats.last_reflection_ms = update.reflection_ms;
}

MotionRemovalSummary Mapper::removeMotion() {
  const auto start = std::chrono::steady_clock::now();
  MotionRemovalSummary summary = classifyActiveRegion();
  revertBehindNewGlass();
  summary.elapsed_ms = millisecondsSince(start);
  return summary;
}

MotionRemovalSummary Mapper::classifyActiveRegion() {
  const auto start = std::chrono::steady_clock::now();
  revertBehindNewGlass();     // the last pass's, if its caller left it
  runDueTick();               // the anchors as the last scan left them
  impl_->reflections.thaw();  // the glass check reads the field again
  MotionRemovalSummary summary;
  static_cast<MotionRemovalCounts&>(summary) =
      impl_->classifier.classify(field_, impl_->anchor_history, map_, impl_->runner.get());
  const RegionClassifier& classifier = impl_->classifier;
  const CellBox new_glass = impl_->classes.replace(classifier.region(), impl_->runner.get());
  impl_->arrivals.clear();  // the classes now judge those objects
  classifier.writeTo(field_.window(), map_);
  summary.new_glass = !new_glass.empty();
  if (summary.new_glass && options_.reflection_removal.reflection_removal_enabled) {
    impl_->reflections.startRevert(new_glass);
  }
  summary.elapsed_ms = millisecondsSince(start);
  MapperStats& stats = impl_->stats;
  stats.last_motion_removal_ms = summary.elapsed_ms;
  stats.free_cells = summary.free_cells;
  stats.occupied_cells = summary.static_cells + summary.glass_cells + summary.metal_cells;
  stats.glass_cells = summary.glass_cells + summary.metal_cells;
  stats.motion_cells = summary.motion_cells;
  return summary;
}

void Mapper::revertBehindNewGlass() {
  revertPartBehindNewGlass(std::numeric_limits<size_t>::max(), 1);
}

void Mapper::revertPartBehindNewGlass() {
  if (!revertPending()) return;
  // A quarter to half of a live scan's own work (0.3 ms on the atrium), so that a replay at 10x
  // (a scan every 1.25 ms) keeps up; a pass's revert then takes about ten scans.
  constexpr size_t kRaysPerPart = 1024;
  // The kept scans refer to the window: what is still pending when the region moves runs whole
  // inside the scan that moves it (up to 20 ms on the atrium). So the parts grow to finish it
  // within half the scans that the robot, going on as over the last scan, takes to move it.
  const size_t pending = impl_->reflections.scansPendingRevert();
  const size_t scans_left = scansUntilRegionMoves(2 * pending);
  const size_t parts_left = std::max<size_t>(scans_left / 2, 1);
  revertPartBehindNewGlass(kRaysPerPart, (pending + parts_left - 1) / parts_left);
}

size_t Mapper::scansUntilRegionMoves(size_t limit) const {
  const Eigen::Vector2d& step = impl_->last_step;
  if (!impl_->last_centre || step.squaredNorm() == 0.0) return limit + 1;
  const Eigen::Vector2d& centre = *impl_->last_centre;
  if (field_.wouldRecenter(centre)) return 0;
  if (!field_.wouldRecenter(centre + static_cast<double>(limit) * step)) return limit + 1;
  // Along a straight line the robot leaves the centre tile once: the first step count that
  // moves the region, by bisection.
  size_t stays = 0, moves = limit;
  while (moves - stays > 1) {
    const size_t middle = stays + (moves - stays) / 2;
    (field_.wouldRecenter(centre + static_cast<double>(middle) * step) ? moves : stays) = middle;
  }
  return moves;
}

bool Mapper::revertPending() const {
  return impl_->reflections.revertPending();
}

void Mapper::revertPartBehindNewGlass(size_t ray_budget, size_t min_scans) {
  if (!impl_->reflections.revertPending()) return;
  const auto start = std::chrono::steady_clock::now();
  impl_->stats.reverted_scans +=
      impl_->reflections.revertSome(ray_budget, min_scans, impl_->inserter, field_);
  impl_->stats.last_motion_removal_ms += millisecondsSince(start);
}

std::vector<RayLabel> Mapper::labelScan(const TimedScan& scan, bool final_map) const {
  if (!scan.scan.validate().empty()) {
    return std::vector<RayLabel>(scan.scan.ranges.size(), RayLabel::kNoReturn);
  }
  return labelValidScan(scan, final_map);
}

std::vector<RayLabel> Mapper::labelValidScan(const TimedScan& scan, bool final_map,
                                             const std::vector<uint8_t>* checked,
                                             const ReflectanceField* inserted) const {
  std::vector<Ray> rays;
  scanToRays(scan.scan, scan.sensor_pose, options_.insertion, rays);
  return labelRays(rays, scan.scan.ranges.size(), impl_->reflections, impl_->classes,
                   field_.activeBox(), field_.geometry(),
                   options_.active_region.active_region_radius, final_map, checked, inserted,
                   inserted ? &impl_->arrivals : nullptr);
}

std::vector<RayLabel> Mapper::labelAddedScan(const TimedScan& scan,
                                             const ScanUpdate& update) const {
  if (!update.error.empty()) return update.labels;  // addScan refused it: every beam NO_RETURN
  // The insertion checked its returns against the classes the labels read (they change only
  // in removeMotion): a whole ray it checked is not checked again, its cut is in update.labels.
  std::vector<RayLabel> labels = labelValidScan(scan, false, &update.checked_returns, &field_);
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

void Mapper::restartEvidence() {
  revertBehindNewGlass();  // the frozen directions are the reverted field's
  impl_->reflections.freeze();
  // Classes live on in the global map; the next scan re-places the window and restores them.
  field_.clear();
  impl_->anchor_history.clear();
  impl_->motion.forgetPrevious();  // the next pass draws what the new evidence shows
  impl_->tick_due = false;
  impl_->scans_since_tick = 0;
  impl_->reflections.forgetScans();
}

void Mapper::forgetDerivedState() {
  impl_->reflections.thaw();
  impl_->reflections.forgetScans();  // and the revert pending on them
  impl_->anchor_history.clear();
  impl_->motion.forgetPrevious();
  impl_->tick_due = false;
  impl_->scans_since_tick = 0;
  impl_->classes.clear();
  impl_->arrivals.clear();
  impl_->classifier.clear();
}

void Mapper::reset() {
  field_.clear();
  map_.clear();
  forgetDerivedState();
  impl_->last_centre.reset();
  impl_->last_step.setZero();
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
  // The window is placed afresh by the next scan; its classes then come from the loaded map.
  forgetDerivedState();
  return true;
}

MapperStats Mapper::stats() const {
  MapperStats stats = impl_->stats;
  // The active region: the field, the anchors' history and the mapper's per-cell classes.
  stats.field_bytes = field_.activeBytes() + impl_->anchor_history.bytes() + impl_->classes.bytes();
  stats.archived_bytes = field_.archivedBytes();
  return stats;
}

}  // namespace rfm
