#pragma once

// Measures of an RFM map against the plain occupancy grid of the same recording (ROS-free).

#include "reflectance_field_map/tools/grid_map_file.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace rfm::tools {

// classes.pgm codes (rfm_offline's contract).
enum ClassCode : uint8_t {
  kCodeUnknown = 0,
  kCodeFree = 1,
  kCodeStatic = 2,
  kCodeGlass = 3,
  kCodeMetal = 4,
  kCodeMotion = 5,
};
constexpr std::size_t kClassCodes = 6;
const char* classCodeName(uint8_t code);

// Where cell (x, y) of map `a` is in map `b`: (x + dx, y + dy).
struct CellOffset {
  int dx = 0;
  int dy = 0;
};

// The offset between two maps of one resolution whose origins lie on one lattice of cells
// (within a thousandth of a cell). Throws MapFileError otherwise.
CellOffset alignment(const GridMap& a, const GridMap& b);

// The class of a map's cell: its classes.pgm code, or from its occupancy when it has no
// classes.pgm (occupied: static); cells beyond the map are unknown.
uint8_t classAt(const GridMap& map, int x, int y);

// Walls kept: of the plain grid's occupied cells, those the RFM also has occupied within
// Chebyshev distance `tolerance` (cells); each cell the RFM dropped is counted by what the RFM
// made of it (its class there).
struct WallsKept {
  std::size_t plain_occupied = 0;
  std::size_t kept = 0;
  std::array<std::size_t, kClassCodes> dropped_by_class{};  // by the RFM's class code
  double percent() const {
    return plain_occupied == 0 ? 100.0 : 100.0 * static_cast<double>(kept) / plain_occupied;
  }
  std::size_t dropped() const { return plain_occupied - kept; }
};
WallsKept measureWallsKept(const GridMap& rfm, const GridMap& plain, int tolerance = 1);

// Whether `map` has an occupied cell within Chebyshev distance `tolerance` of cell (x, y).
bool occupiedWithin(const GridMap& map, int x, int y, int tolerance);

// Cells of each class code in a map (its classes.pgm, or its occupancy).
std::array<std::size_t, kClassCodes> countClasses(const GridMap& map);

}  // namespace rfm::tools
