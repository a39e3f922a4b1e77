// Reflection removal (Alg. 3): rays that passed through glass lose their evidence beyond it.
#pragma once

#include "reflectance_field_map/core/active_classes.h"
#include "reflectance_field_map/core/frozen_reflectivity.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/reflectance_field.h"
#include "reflectance_field_map/core/scan_inserter.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

namespace rfm {

namespace detail {
class PassThroughDetector;
}  // namespace detail

// Checks rays against the glass, metal and static cells of the active region (ActiveClasses)
// and cuts those that pass through one just past it: their misses beyond it and their hit are
// discarded, as Alg. 3 discards evidence beyond glass. Online, it also keeps the latest scans as
// inserted and, when motion removal finds new glass, takes back their evidence from beyond it.
class ReflectionRemover {
 public:
  // `field` and `classes` must outlive this.
  ReflectionRemover(const ReflectionRemovalOptions& options, const ReflectanceField& field,
                    const ActiveClasses& classes);

  // Whether rays are checked at all: reflection removal is on and some cell blocks rays.
  bool checks() const { return enabled_ && classes_.anyBlocking(); }

  // For rays inside the window: the distance along each of the first blocking cell it passes
  // through, negative where it passes none (distances[0, count)). A blocking cell is glass or
  // metal, or static, reflective over at least static_blocking_min_angle and not in or next to
  // the ray's direction (for a ray with a return; beside glass or metal, not in it); the ray
  // must cross it near a cell centre and leave it more than penetration_tolerance before its end.
  void passThroughDistances(const Ray* rays, size_t count, double* distances) const;
  // Cuts the rays (inside the window) that pass through a blocking cell just past it; each
  // return cut becomes REFLECTION in labels (by beam). With a runner, rays on its threads.
  // Returns the number of returns cut.
  size_t cut(std::vector<Ray>& rays, std::vector<RayLabel>& labels, ParallelRunner* runner) const;

  // Until thaw(), the check reads the directions the static cells of the window reflected in
  // as they are now, not as the field has them then: a batch pass rebuilding the evidence then
  // depends on no scan of its own, so its scans may go in side by side.
  void freeze();
  void thaw() { frozen_.clear(); }
  bool frozen() const { return frozen_.active(); }

  // Online re-processing. Keeps a scan's rays as inserted (inside the window, cut at the glass
  // known then) from `origin`, beam 0 heading `first_beam_angle` (world, rad) and the next ones
  // `increment` apart, their ends up to `end_spread` (m) off their beams' lines (a swept scan,
  // LaserScan2D::sweep_shift); the latest scan_buffer_size scans are kept.
  void keep(const std::vector<Ray>& rays, const Eigen::Vector2d& origin, double first_beam_angle,
            double increment, double end_spread);
  // Forgets the kept scans and any revert pending on them (the window moved, or the evidence
  // restarts).
  void forgetScans() {
    buffer_.clear();
    revert_pending_ = 0;
  }
  // New glass appeared in `new_glass`: the kept scans whose rays pass through it added
  // evidence beyond it, which is taken back exactly (their de-duplicated updates replayed with
  // and without it; a revert never moves a bin past the prior). startRevert marks the scans kept
  // so far (scans kept later were cut at this glass already); revertSome takes back the marked
  // scans, so that a caller can spread a revert over the scans that follow it. It goes newest
  // first: the latest scans' evidence is what the next scans' labels meet. Until the revert is
  // done, no scan leaves the buffer.
  void startRevert(const CellBox& new_glass);
  bool revertPending() const { return revert_pending_ > 0; }
  size_t scansPendingRevert() const { return revert_pending_; }
  // Reverts marked scans until `ray_budget` of their rays were checked or replayed and at least
  // `min_scans` scans were reverted (at least one, when any is marked); returns how many.
  size_t revertSome(size_t ray_budget, size_t min_scans, ScanInserter& inserter,
                    ReflectanceField& field);

 private:
  // A scan as inserted, kept for online re-processing.
  struct KeptScan {
    std::vector<Ray> rays;    // in beam order
    Eigen::Vector2d origin;   // of every ray (the sensor, inside the window)
    double first_beam_angle;  // world direction of beam 0, rad
    double increment;         // rad between beams
    double end_spread;        // m a ray's end may lie off its beam's line (a swept scan)
  };

  // The check of one ray from `from` m along it on, leaping where the clearance allows by
  // `leap_unit` m per cell of clearance.
  double walkTowardsGlass(const Ray& ray, detail::PassThroughDetector& detector, double from,
                          double leap_unit) const;
  // Cuts a ray `along` m from its origin, where the check found glass (false if negative).
  bool cutAtDistance(double along, Ray& ray) const;
  // Takes back one kept scan's evidence beyond revert_box_; returns the rays it checked and
  // replayed.
  size_t revertScan(KeptScan& kept, ScanInserter& inserter, ReflectanceField& field);

  bool enabled_;
  double penetration_tolerance_;
  size_t buffer_size_;
  int static_blocking_min_bins_;
  const ReflectanceField& field_;
  const ActiveClasses& classes_;
  FrozenReflectivity frozen_;
  std::deque<KeptScan> buffer_;
  // The pending revert: the new glass, and how many of the oldest kept scans are still to revert.
  CellBox revert_box_;
  size_t revert_pending_ = 0;
  // revertScan's working memory, kept across calls: a revert is spread over many of them.
  struct RevertScratch {
    std::vector<BinUpdate> before, after;
    std::vector<Ray> old_rays, new_rays;
    std::vector<std::pair<size_t, Ray>> truncated;  // index in the scan, ray cut at the glass
    std::vector<uint8_t> bin_changed;
    std::vector<BeamRange> beam_ranges;
    std::vector<uint8_t> slot_marks;  // applyDifference's, one per window slot
  };
  RevertScratch scratch_;
};

}  // namespace rfm
