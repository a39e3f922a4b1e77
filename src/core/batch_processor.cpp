#include "reflectance_field_map/core/batch_processor.h"

#include "reflectance_field_map/core/detail/glass_passes.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/plain_occupancy_grid.h"
#include "reflectance_field_map/core/ray_insertion.h"
#include "reflectance_field_map/core/ray_labels.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace rfm {
namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Calls visit(ray) for each of a scan's rays as far as it adds evidence: within the
// active-region radius, as live.
template <typename Visit>
void forEachEvidenceRay(const TimedScan& scan, const MapperOptions& options, Visit&& visit) {
  const double radius = options.active_region.active_region_radius;
  forEachBeamRay(scan.scan, scan.sensor_pose, options.insertion, [&](Ray ray) {
    clipRayToLength(radius, ray);
    visit(ray);
  });
}

// Those rays, in beam order, in `rays` (cleared first).
void evidenceRays(const TimedScan& scan, const MapperOptions& options, std::vector<Ray>& rays) {
  rays.clear();
  rays.reserve(scan.scan.ranges.size());
  forEachEvidenceRay(scan, options, [&rays](const Ray& ray) { rays.push_back(ray); });
}

// The square region holding every sensor origin and all evidence (rays up to the active-region
// radius): the batch keeps the whole recording in one window centred on it, so motion removal and
// labelling see it all.
struct Extent {
  Eigen::Vector2d centre{0.0, 0.0};
  double half_side = 0.0;
};

Extent recordingExtent(const std::vector<TimedScan>& scans, const MapperOptions& options) {
  // Scan by scan on the mapper's number of threads, each with its own bounds.
  ParallelRunner runner(options.insertion.insertion_threads);
  struct alignas(64) Bounds {
    Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d high = -low;
  };
  std::vector<Bounds> parts(runner.threads());
  parallelFor(&runner, scans.size(), 16, [&](size_t i, int thread) {
    const TimedScan& scan = scans[i];
    if (!scan.scan.validate().empty()) return;
    // The rays' ends, taken one by one, none stored.
    Bounds bounds = parts[thread];
    bounds.low = bounds.low.cwiseMin(scan.sensor_pose.position);
    bounds.high = bounds.high.cwiseMax(scan.sensor_pose.position);
    forEachEvidenceRay(scan, options, [&](const Ray& ray) {
      bounds.low = bounds.low.cwiseMin(ray.end);
      bounds.high = bounds.high.cwiseMax(ray.end);
    });
    parts[thread] = bounds;
  });
  Bounds all;
  for (const Bounds& part : parts) {
    all.low = all.low.cwiseMin(part.low);
    all.high = all.high.cwiseMax(part.high);
  }
  Extent extent;
  if (!std::isfinite(all.low.x())) return extent;
  extent.centre = 0.5 * (all.low + all.high);
  extent.half_side = 0.5 * (all.high - all.low).maxCoeff();
  return extent;
}

// Cells that block rays (glass, metal, static) in the map, for convergence tests.
detail::GlassCells blockingCells(const GlobalMap2D& map) {
  detail::GlassCells cells;
  const CellBox box = map.bounds();
  std::vector<CellClass> classes;
  map.extract(box, classes);
  size_t i = 0;
  for (int y = box.min.y(); y < box.max.y(); ++y) {
    for (int x = box.min.x(); x < box.max.x(); ++x, ++i) {
      if (blocksRays(classes[i]) && classes[i] != CellClass::kStatic) cells.insert({x, y});
    }
  }
  return cells;
}

BatchResult processPlainGrid(const std::vector<TimedScan>& scans, MapperOptions options,
                             const Extent& extent,
                             const std::function<void(size_t, size_t)>& progress) {
  BatchResult result;
  PlainOccupancyGrid grid(options.grid, options.log_odds, options.active_region,
                          extent.half_side + options.grid.resolution);
  grid.recenter(extent.centre);
  std::vector<Ray> rays;
  auto start = std::chrono::steady_clock::now();
  for (size_t i = 0; i < scans.size(); ++i) {
    if (scans[i].scan.validate().empty()) {
      // The same evidence as the RFM's (Table II compares the two on the same rays).
      evidenceRays(scans[i], options, rays);
      grid.insert(rays);
    }
    if (progress) progress(i + 1, 2 * scans.size());
  }
  result.timings.insert_ms = millisecondsSince(start);

  const CellBox box = grid.window().box();
  const GridGeometry geometry(options.grid.resolution, options.grid.theta_bins);
  auto class_of = [&](const CellIndex& cell) {
    if (!box.contains(cell)) return CellClass::kUnknown;
    const int8_t v = grid.value(cell);
    return v > 0 ? CellClass::kOccupied : (v < 0 ? CellClass::kFree : CellClass::kUnknown);
  };
  result.map.assign(box, class_of);
  start = std::chrono::steady_clock::now();
  result.labels.resize(scans.size());
  for (size_t i = 0; i < scans.size(); ++i) {
    std::vector<RayLabel>& labels = result.labels[i];
    labels.assign(scans[i].scan.ranges.size(), RayLabel::kNoReturn);
    if (scans[i].scan.validate().empty()) {
      scanToRays(scans[i].scan, scans[i].sensor_pose, options.insertion, rays);
      for (const Ray& ray : rays) {
        if (!ray.hit) continue;
        labels[ray.beam] =
            labelEndpoint(ray, geometry, options.active_region.active_region_radius,
                          /*final_map=*/true, class_of, [](const CellIndex&) { return false; });
      }
    }
    if (progress) progress(scans.size() + i + 1, 2 * scans.size());
  }
  result.timings.labelling_ms = millisecondsSince(start);
  return result;
}

}  // namespace

std::vector<const TimedScan*> everyNthScanOfEachSensor(const std::vector<TimedScan>& scans,
                                                       int stride) {
  std::vector<const TimedScan*> kept;
  std::unordered_map<uint32_t, size_t> seen;  // scans of each sensor so far
  for (const TimedScan& scan : scans) {
    if (seen[scan.sensor_id]++ % stride == 0) kept.push_back(&scan);
  }
  return kept;
}

BatchResult processBatch(const std::vector<TimedScan>& scans, const MapperOptions& requested,
                         const BatchOptions& batch, BatchMode mode,
                         const std::function<void(size_t, size_t)>& progress,
                         const std::function<void(const ReflectanceField&)>& inspect_field) {
  requested.validate();
  batch.validate();
  const Extent extent = recordingExtent(scans, requested);
  if (extent.half_side + requested.grid.resolution > MapperLayout::kMaxWindowRadius) {
    throw std::invalid_argument(
        "the recording's evidence spans " + std::to_string(static_cast<int>(2 * extent.half_side)) +
        " m: the batch holds it in one window, at most " +
        std::to_string(static_cast<int>(2 * MapperLayout::kMaxWindowRadius)) + " m across");
  }
  if (mode == BatchMode::kPlainGrid) return processPlainGrid(scans, requested, extent, progress);

  MapperOptions options = requested;
  // The mode switches stages off; it never switches on one the options disabled.
  options.motion_removal.motion_removal_enabled &= mode != BatchMode::kBasicRfm;
  options.reflection_removal.reflection_removal_enabled &= mode == BatchMode::kFull;
  options.reflection_removal.scan_buffer_size = 0;  // batch re-processes every scan instead
  options.occupancy.beta = batch.batch_beta;        // classifies the whole recording seen
  MapperLayout layout;
  layout.window_radius = extent.half_side + options.grid.resolution;

  Mapper mapper(options, layout);
  mapper.holdActiveRegionAt(extent.centre);
  BatchResult result;
  const ReflectionRemovalOptions& reflection = options.reflection_removal;
  const int passes = mode == BatchMode::kFull && reflection.reflection_removal_enabled
                         ? batch.max_reflection_iterations + 1
                         : 1;
  // Passes before the last only find glass for the next one's cuts: they take fewer scans.
  auto stride_of = [&](int pass) {
    if (pass + 1 == passes) return 1;
    return pass == 0 ? batch.first_pass_scan_stride : batch.search_pass_scan_stride;
  };
  // Each pass's scans, by pointer: the recording is not copied.
  std::vector<std::vector<const TimedScan*>> scans_by_pass(passes);
  for (int pass = 0; pass < passes; ++pass)
    scans_by_pass[pass] = everyNthScanOfEachSensor(scans, stride_of(pass));
  size_t total_steps = scans.size();  // labelling
  for (int pass = 0; pass < passes; ++pass)
    total_steps += scans_by_pass[pass].size();
  size_t done = 0;
  detail::GlassPasses glass_passes;
  bool settled = false;  // a pass of fewer scans converged: the last pass follows at once
  for (int pass = 0; pass < passes; ++pass) {
    const std::vector<const TimedScan*>& inserted = scans_by_pass[pass];
    if (pass > 0) mapper.restartEvidence();
    auto start = std::chrono::steady_clock::now();
    // In chunks, so the progress bar moves while the threads insert.
    constexpr size_t kChunk = 256;
    for (size_t first = 0; first < inserted.size(); first += kChunk) {
      const size_t last = std::min(inserted.size(), first + kChunk);
      mapper.addScans({inserted.begin() + first, inserted.begin() + last});
      done += last - first;
      if (progress) progress(done, total_steps);
    }
    result.timings.insert_ms += millisecondsSince(start);
    start = std::chrono::steady_clock::now();
    mapper.removeMotion();
    result.timings.motion_removal_ms += millisecondsSince(start);
    if (passes == 1) break;
    ++result.timings.reflection_iterations;

    const detail::GlassPassOutcome outcome = glass_passes.add(blockingCells(mapper.map()));
    const bool converged = outcome == detail::GlassPassOutcome::kConverged;
    if (pass + 1 == passes) {
      // Compared with a pass of fewer scans that had already settled, the glass says nothing new.
      if (!settled) result.timings.reflection_converged = converged;
      break;
    }
    if (outcome == detail::GlassPassOutcome::kChanged) continue;
    result.timings.reflection_converged = converged;
    // A pass that took every scan is final; after one that took fewer, the last pass follows.
    if (stride_of(pass) == 1) break;
    settled = true;
    for (int skipped = pass + 1; skipped + 1 < passes; ++skipped)
      total_steps -= scans_by_pass[skipped].size();
    pass = passes - 2;
  }
  done = total_steps - scans.size();

  if (inspect_field) inspect_field(mapper.field());
  const auto start = std::chrono::steady_clock::now();
  // In chunks, so the progress bar moves while the threads label.
  constexpr size_t kChunk = 256;
  result.labels.reserve(scans.size());
  for (size_t first = 0; first < scans.size(); first += kChunk) {
    const size_t last = std::min(scans.size(), first + kChunk);
    for (std::vector<RayLabel>& labels :
         mapper.labelScans(scans.begin() + first, scans.begin() + last, /*final_map=*/true)) {
      result.labels.push_back(std::move(labels));
    }
    done += last - first;
    if (progress) progress(std::min(total_steps, done), total_steps);
  }
  result.timings.labelling_ms = millisecondsSince(start);
  if (progress) progress(total_steps, total_steps);
  result.map = mapper.releaseMap();
  return result;
}

}  // namespace rfm
