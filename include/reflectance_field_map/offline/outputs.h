#pragma once

#include "reflectance_field_map/core/batch_processor.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/offline/bag_input.h"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfm {
namespace offline {

// An output file can't be written: what() names it.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Creates `dir` (and parents). Throws OutputError.
void makeOutputDirectory(const std::string& dir);

// map_server format: `dir`/`stem`.pgm (P5, 254 free or motion, 0 obstacle, 205 unknown,
// y up) and `dir`/`stem`.yaml (image, resolution, origin [x, y, 0], negate 0,
// occupied_thresh 0.65, free_thresh 0.196). The picture covers map.bounds() (one unknown
// cell at the origin when the map is empty).
void writeMapServerFiles(const std::string& dir, const std::string& stem, const GlobalMap2D& map,
                         double resolution);

// labels.bag: one reflectance_field_map/RayLabels per scan on `topic`, header copied from the
// scan (seq, stamp, frame_id), recorded at the scan's bag time. Beam order is the bag's.
void writeLabelsBag(const std::string& path, const std::string& topic, const BagScans& input,
                    const std::vector<std::vector<RayLabel>>& labels);

// Everything summary.json reports.
struct RunSummary {
  std::string bag;
  std::string mode;        // selectMode() name
  std::string batch_mode;  // the BatchMode passed to processBatch
  std::string fixed_frame;
  std::string base_frame;
  const BagScans* input = nullptr;
  const BatchResult* result = nullptr;
  const MapperOptions* options = nullptr;
  std::map<std::string, double> stage_seconds;  // read_bag, process, write_outputs, ...
  double wall_seconds = 0.0;
  std::vector<std::string> files;
  std::vector<std::string> notes;  // besides the input's notes
};

// Label counts by RayLabel value: no_return, kept, motion, reflection.
std::map<std::string, uint64_t> countLabels(const std::vector<std::vector<RayLabel>>& labels);
// Cells of each class in the map's bounds, by toString(CellClass).
std::map<std::string, uint64_t> countClasses(const GlobalMap2D& map);

void writeSummaryJson(const std::string& path, const RunSummary& summary);

}  // namespace offline
}  // namespace rfm
