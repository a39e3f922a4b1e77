#pragma once

// Maps as rfm_offline writes them (and map_server reads them): DIR/map.yaml with its image, and
// DIR/classes.pgm beside it. ROS-free; every size read from a file is checked.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfm::tools {

// A map file can't be read or is not what it should be: what() names it and says why.
class MapFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Occupancy : uint8_t { kUnknown, kFree, kOccupied };

// A 2D grid in the map frame: cell (x, y) covers [origin_x + x * resolution, + resolution) in x,
// likewise in y; row 0 is the lowest y (the image's bottom row).
struct GridMap {
  int width = 0;
  int height = 0;
  double resolution = 0.0;
  double origin_x = 0.0;
  double origin_y = 0.0;
  std::vector<Occupancy> occupancy;  // width * height, x fastest
  std::vector<uint8_t> classes;      // classes.pgm codes in the same layout; empty if absent

  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
           static_cast<std::size_t>(x);
  }
  Occupancy occupancyAt(int x, int y) const { return occupancy[index(x, y)]; }
  bool hasClasses() const { return !classes.empty(); }
};

// The most cells a map may have (a 400 m square at 2 cm): larger headers are refused.
constexpr std::size_t kMaxMapCells = std::size_t{20000} * 20000;

// An 8-bit binary PGM (P5, maxval <= 255): pixels row by row from the top.
struct PgmImage {
  int width = 0;
  int height = 0;
  int max_value = 0;
  std::vector<uint8_t> pixels;
};
PgmImage readPgm(const std::string& path);

// A map_server map: the YAML's image (relative to the YAML), resolution, origin (its yaw must be
// 0), negate, occupied_thresh and free_thresh, read with map_server's trinary rule
// (p = (255 - v) / 255, or v / 255 when negated: occupied above occupied_thresh, free below
// free_thresh, unknown between).
GridMap readMapServerMap(const std::string& yaml_path);

// DIR/map.yaml, and DIR/classes.pgm when it exists (which must have the map's size).
GridMap readMapDirectory(const std::string& dir);

}  // namespace rfm::tools
