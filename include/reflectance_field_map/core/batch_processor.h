#pragma once

#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/mapper.h"
#include "reflectance_field_map/core/options.h"

#include <functional>
#include <string>
#include <vector>

namespace rfm {

// Which pipeline the offline tool runs (Table II baseline and the Table III ablation).
enum class BatchMode {
  kPlainGrid,      // --baseline: plain 2D occupancy grid
  kBasicRfm,       // --no-motion-removal --no-reflection-removal
  kMotionRemoval,  // --no-reflection-removal
  kFull,           // motion + reflection removal
};

struct BatchTimings {
  double insert_ms = 0.0;
  double motion_removal_ms = 0.0;
  double reflection_removal_ms = 0.0;
  double labelling_ms = 0.0;
  int reflection_iterations = 0;
  bool reflection_converged = true;
};

struct BatchResult {
  GlobalMap2D map;                            // final classes of every explored cell
  std::vector<std::vector<RayLabel>> labels;  // per input scan, per beam
  BatchTimings timings;
};

// Every `stride`th scan of each sensor (by sensor_id), in their order: the scans a batch pass
// that only searches for glass inserts (BatchOptions::first_pass_scan_stride and
// search_pass_scan_stride).
std::vector<const TimedScan*> everyNthScanOfEachSensor(const std::vector<TimedScan>& scans,
                                                       int stride);

// Processes a whole recording: builds the map from every scan, runs motion removal and
// iterative reflection removal over the final field and labels every beam against the final
// map. Alg. 3's passes before the last take every Nth scan of each sensor (`batch`'s
// first_pass_scan_stride and search_pass_scan_stride); the last takes every scan. Uses the
// same Mapper code as the live node, with `batch.batch_beta` in place of beta.
// `progress(done, total)` may be empty.
// `inspect_field`, when set, sees the final reflectance field (e.g. for theta-resolved pictures).
// Throws std::invalid_argument when the recording is too large for one window
// (MapperLayout::kMaxWindowRadius).
BatchResult processBatch(const std::vector<TimedScan>& scans, const MapperOptions& options,
                         const BatchOptions& batch, BatchMode mode,
                         const std::function<void(size_t, size_t)>& progress = {},
                         const std::function<void(const ReflectanceField&)>& inspect_field = {});

}  // namespace rfm
