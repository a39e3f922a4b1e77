#pragma once

#include "reflectance_field_map/core/batch_processor.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/offline/bag_input.h"

#include <cstdint>
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

// classes.pgm codes (a contract: users' tools and rfm_eval read them).
constexpr uint8_t kClassCodeUnknown = 0;
constexpr uint8_t kClassCodeFree = 1;
constexpr uint8_t kClassCodeStatic = 2;
constexpr uint8_t kClassCodeGlass = 3;
constexpr uint8_t kClassCodeMetal = 4;
constexpr uint8_t kClassCodeMotion = 5;

// The classes.pgm code of a class. An obstacle no rule classified (CellClass::kOccupied: the
// plain grid, --no-motion-removal) is static.
uint8_t classCode(CellClass c);

// `dir`/classes.pgm: the geometry of map.pgm (same cells, width, height and row order, so
// map.yaml's origin and resolution hold for it), P5 with maxval 255, one byte per cell holding
// classCode().
void writeClassesPgm(const std::string& dir, const GlobalMap2D& map);

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
  const BatchOptions* batch = nullptr;
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
