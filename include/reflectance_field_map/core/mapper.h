// The mapper that the node, the nodelet and the offline tool drive: the paper's steps in order.
#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/motion_removal.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rfm {

class AnchorHistory;

// One scan with the poses it was taken from, in the fixed frame (REP-105: odom or map).
struct TimedScan {
  uint32_t sensor_id = 0;  // index of the scan's source (topic)
  double stamp = 0.0;      // s
  LaserScan2D scan;
  Pose2D sensor_pose;  // laser frame in the fixed frame at `stamp`
  Pose2D robot_pose;   // base frame in the fixed frame at `stamp`: centre of the active region
};

// What adding one scan did.
struct ScanUpdate {
  // Provisional per-beam labels: NO_RETURN, REFLECTION (passed through known glass, its
  // evidence beyond the glass discarded) or KEPT. Motion is decided by removeMotion().
  std::vector<RayLabel> labels;
  std::string error;  // non-empty: the scan was malformed and rejected (nothing inserted)
  size_t bin_updates = 0;
  bool region_moved = false;
  bool shared = false;  // the mapper's helper threads took part (see Mapper::addScan)
  // By beam: 1 where the insertion's glass check saw the whole ray of a return (neither the
  // active region nor the window shortened it): labelAddedScan takes that check's answer.
  // Set by addScan only.
  std::vector<uint8_t> checked_returns;
  double insert_ms = 0.0;
  double reflection_ms = 0.0;
};

struct MotionRemovalSummary : MotionRemovalCounts {
  bool new_glass = false;  // glass appeared where there was none: buffered scans re-processed
  double elapsed_ms = 0.0;
};

struct MapperStats {
  uint64_t scans_processed = 0;
  uint64_t rays_inserted = 0;
  uint64_t reflection_rays = 0;
  double last_insert_ms = 0.0;
  double last_reflection_ms = 0.0;
  double last_motion_removal_ms = 0.0;
  uint64_t reverted_scans = 0;  // kept scans taken back from beyond new glass (online Alg. 3)
  size_t occupied_cells = 0;    // in the active region, after the last motion removal
  size_t free_cells = 0;
  size_t glass_cells = 0;
  size_t motion_cells = 0;
  size_t field_bytes = 0;
  size_t archived_bytes = 0;
};

// How a mapper holds its region, beyond the user's parameters.
struct MapperLayout {
  // About 14 GB of field at 5 cm and 180 bins.
  static constexpr double kMaxWindowRadius = 200.0;  // m
  // m: a window wider than the active region needs (0: none). A batch holds a whole recording in
  // one window; its rays still add evidence only within active_region_radius of their sensor.
  double window_radius = 0.0;
  // The reflection check leaps by a clearance map kept in blocks of 2^clearance_block_shift
  // cells a side (ClearanceMap). Single cells let rays leap to a cell from structure, so most
  // rays that end on a wall never walk cell by cell; larger blocks rebuild faster at each motion
  // removal and placement of the window, but every ray then walks its last blocks.
  int clearance_block_shift = 0;
};

// The one mapper that the node, the nodelet and the offline tool drive. Not thread-safe:
// callers serialise addScan / removeMotion.
class Mapper {
 public:
  // Throws InvalidOption (naming the field) when `options` or `layout` are out of range.
  explicit Mapper(const MapperOptions& options, const MapperLayout& layout = MapperLayout());
  ~Mapper();
  Mapper(const Mapper&) = delete;
  Mapper& operator=(const Mapper&) = delete;

  const MapperOptions& options() const { return options_; }

  // Re-centres the active region on the robot, cuts the rays at known glass (reflection
  // removal, Alg. 3) and inserts them (Alg. 1). The anchor rules' persistence tick that the scan
  // makes due (every 1 / motion_removal_rate s of the scans' clock) waits for runDueTick(), which
  // the next addScan, addScans or removeMotion runs first, so that it reads the field exactly as
  // this scan left it: a live caller runs it once the scan's labels are out, off its latency.
  // A scan that comes within ParallelRunner::kSpinTime of the last addScan's return shares the
  // work with the mapper's helper threads (insertion_threads); a later one, as live scans come,
  // is done by the caller alone. Either way the field and the labels come out the same.
  ScanUpdate addScan(const TimedScan& scan);
  // Runs the persistence tick that the last scan made due, if any (see addScan).
  void runDueTick();

  // addScan on each scan in turn, with the same result, for a batch: scans between window moves
  // and persistence ticks are inserted theta bin by theta bin (no per-scan ScanUpdate).
  using ScanIterator = std::vector<TimedScan>::const_iterator;
  void addScans(ScanIterator first, ScanIterator last);
  // The same for scans picked by pointer (a batch's sparser passes), none of them copied.
  void addScans(const std::vector<const TimedScan*>& scans);

  // From now on the active region stays centred on `centre`, whatever the scans' robot poses:
  // a batch holds a whole recording in one window (reset() does not undo it).
  void holdActiveRegionAt(const Eigen::Vector2d& centre);

  // Motion removal (Alg. 2) over the active region, glass completion, then writes the region's
  // classes into the global map. When new glass appears, the buffered scans' evidence beyond it
  // is taken back (online Alg. 3).
  MotionRemovalSummary removeMotion();
  // removeMotion() in its two steps, for a caller that publishes the map between them: after
  // classifyActiveRegion() the classes and the global map are final (elapsed_ms is this step's);
  // revertBehindNewGlass() then takes back the evidence beyond new glass, a pass's longest part
  // when it finds some. A live caller spreads it instead over the scans that follow, one
  // revertPartBehindNewGlass() (a fraction of a scan's own work) after each scan's labels are
  // out; the parts grow as the robot nears a move of the active region, so that they end before
  // it. Whatever is still pending runs first when the next pass or evidence restart comes or the
  // active region moves (save() writes the field as it is).
  MotionRemovalSummary classifyActiveRegion();
  void revertBehindNewGlass();
  void revertPartBehindNewGlass();
  bool revertPending() const;

  // Classes of the explored map (global, survives the active region moving on).
  const GlobalMap2D& map() const { return map_; }
  // Box of map cells changed since the last call (for incremental map updates).
  CellBox takeMapChanges() { return map_.takeChangedBox(); }
  // Hands the map over (the mapper's map is empty afterwards).
  GlobalMap2D releaseMap() { return std::exchange(map_, GlobalMap2D()); }
  const ReflectanceField& field() const { return field_; }
  const AnchorHistory& anchorHistory() const;
  // Class of a cell: from the active region when inside it, else from the global map.
  CellClass cellClass(const CellIndex& cell) const;

  // Per-beam labels of a scan against the current map (paper Sec. VI-A, labelRays): NO_RETURN,
  // KEPT when the endpoint cell is an obstacle and the ray did not pass through glass first,
  // REFLECTION when it did, MOTION when the endpoint is motion. With `final_map` an endpoint
  // whose evidence did not survive (free or unknown) is removed as MOTION too; live, it is kept
  // until motion removal has judged it (labelAddedScan, below, judges arrivals at once).
  std::vector<RayLabel> labelScan(const TimedScan& scan, bool final_map = false) const;
  // labelScan of a scan just added (live), with `update` its addScan result: a beam the
  // insertion cut at glass is REFLECTION whatever the map says now, and a return whose whole ray
  // the insertion checked is not checked again (the check read the same classes; only the
  // scan's own evidence, inserted since, could move a static cell's directions). A return in a
  // cell last classified free, where the field had seen it free in the beam's direction before
  // (a person stepping into open floor), is MOTION before motion removal sees the person move,
  // and so are the returns of the scans after it in that cell or beside it until the next
  // classification (ArrivalMarks): labels depend on the scans labelled before them since then.
  std::vector<RayLabel> labelAddedScan(const TimedScan& scan, const ScanUpdate& update) const;
  // labelScan of the scans [first, last), on the mapper's threads.
  std::vector<std::vector<RayLabel>> labelScans(ScanIterator first, ScanIterator last,
                                                bool final_map = false) const;

  // Discards all reflectance evidence but keeps the current classes, so the next scans are
  // checked against the glass found so far (batch re-processing, Alg. 3 step 2). Until the next
  // removeMotion(), that check reads the directions the active region's static cells reflected
  // in as they are now (ReflectionRemover::freeze): it then depends on no scan before, so
  // addScans still inserts scans in groups.
  void restartEvidence();

  void reset();
  // Faults the field's memory in now. A new or reset mapper's field takes its pages as the first
  // scans reach them, which can hold a live mapper's first scan for a fifth of a second on the
  // shared VM: a live caller calls this once it has created or reset the mapper.
  void prefault() { field_.prefault(); }
  void save(std::ostream& out) const;
  // False (and the mapper unchanged) when the stream is not a compatible saved state.
  bool load(std::istream& in);

  MapperStats stats() const;

 private:
  struct Impl;
  // The steps of addScan before the insertion: placeScan validates the scan and re-centres the
  // window on the robot; makeRays makes its rays within the active region. finishScan does what
  // follows the insertion: countScan (a persistence tick made due) and keepInsertedRays
  // (statistics, the scans kept for online re-processing), which addScans calls apart because it
  // inserts a group's rays after counting its scans.
  ScanUpdate placeScan(const TimedScan& scan);
  // addScan's work, with the helper threads or without them.
  ScanUpdate addScanSharing(const TimedScan& scan, bool share);
  const Eigen::Vector2d& regionCentre(const TimedScan& scan) const;
  void makeRays(const TimedScan& scan, std::vector<Ray>& rays, ScanUpdate& update) const;
  void finishScan(const TimedScan& scan, const std::vector<Ray>& rays, const ScanUpdate& update);
  // Reverts pending scans until `ray_budget` of their rays were checked or replayed and at least
  // `min_scans` scans were reverted.
  void revertPartBehindNewGlass(size_t ray_budget, size_t min_scans);
  // Scans until the active region moves if the robot goes on as over the last scan (0: the next
  // moves it), or limit + 1 when not within `limit` scans.
  size_t scansUntilRegionMoves(size_t limit) const;
  void countScan(double stamp);
  void keepInsertedRays(const TimedScan& scan, const std::vector<Ray>& rays);
  bool tickDue(double stamp) const;
  // What reset() and load() start afresh besides the field and the map.
  void forgetDerivedState();
  // labelScan of a scan already validated; beams marked in `checked` (by beam, may be null)
  // are not checked for passing through glass again; `inserted` (may be null): the field holding
  // the scan's hits, which tells arrivals in free cells (labelRays).
  std::vector<RayLabel> labelValidScan(const TimedScan& scan, bool final_map,
                                       const std::vector<uint8_t>* checked = nullptr,
                                       const ReflectanceField* inserted = nullptr) const;

  MapperOptions options_;
  ReflectanceField field_;
  GlobalMap2D map_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rfm
