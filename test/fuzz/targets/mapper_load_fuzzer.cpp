// A saved state (.rfm) as ~load_map reads it: Mapper::load, and for a state it accepts what the
// node does next: a scan that moves the window over the loaded tiles (their archived evidence
// comes back), motion removal, and the map published over its bounds.
#include "small_mapper.h"

#include "reflectance_field_map/core/mapper.h"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace {

// A scan of 90 beams about 2 m away, from the origin.
rfm::TimedScan probeScan() {
  rfm::TimedScan timed;
  timed.scan.angle_min = -1.5f;
  timed.scan.angle_increment = 3.0f / 89.0f;
  timed.scan.angle_max = 1.5f;
  timed.scan.range_min = 0.1f;
  timed.scan.range_max = 20.0f;
  timed.scan.ranges.assign(90, 2.0f);
  return timed;
}

// The node publishes /rfm/map over the map's bounds. Until .rfm reading bounds the map's extent
// (issue 36, deliverable 2, on its own branch), a state whose tiles lie far apart would make
// that one allocation of many gigabytes: larger maps are not drawn here.
constexpr int64_t kMaxDrawnCells = int64_t{1} << 26;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static rfm::Mapper mapper(rfm::fuzz::smallMapperOptions());
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  if (!mapper.load(in)) return 0;
  mapper.addScan(probeScan());
  mapper.removeMotion();
  const rfm::CellBox bounds = mapper.map().bounds();
  const int64_t width = int64_t{bounds.max.x()} - bounds.min.x();
  const int64_t height = int64_t{bounds.max.y()} - bounds.min.y();
  if (!bounds.empty() && width * height <= kMaxDrawnCells) {
    std::vector<rfm::CellClass> classes;
    mapper.map().extract(bounds, classes);
  }
  mapper.reset();
  return 0;
}
