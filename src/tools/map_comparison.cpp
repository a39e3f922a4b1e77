#include "reflectance_field_map/tools/map_comparison.h"

#include <cmath>
#include <cstdio>

namespace rfm::tools {
namespace {

// Origins this close to a whole number of cells apart share a lattice.
constexpr double kLatticeTolerance = 1e-3;

std::string format(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6f", value);
  return text;
}

int wholeCells(double metres, double resolution, const char* axis) {
  const double cells = metres / resolution;
  const double whole = std::round(cells);
  if (std::abs(cells - whole) > kLatticeTolerance) {
    throw MapFileError(std::string("the maps' origins are ") + format(cells) + " cells apart in " +
                       axis + ": not on one grid");
  }
  return static_cast<int>(whole);
}

}  // namespace

const char* classCodeName(uint8_t code) {
  switch (code) {
    case kCodeUnknown:
      return "unknown";
    case kCodeFree:
      return "free";
    case kCodeStatic:
      return "static";
    case kCodeGlass:
      return "glass";
    case kCodeMetal:
      return "metal";
    case kCodeMotion:
      return "motion";
    default:
      return "invalid";
  }
}

CellOffset alignment(const GridMap& a, const GridMap& b) {
  if (std::abs(a.resolution - b.resolution) > 1e-9 * a.resolution) {
    throw MapFileError("the maps' resolutions differ: " + format(a.resolution) + " and " +
                       format(b.resolution) + " m");
  }
  return {wholeCells(a.origin_x - b.origin_x, a.resolution, "x"),
          wholeCells(a.origin_y - b.origin_y, a.resolution, "y")};
}

uint8_t classAt(const GridMap& map, int x, int y) {
  if (!map.contains(x, y)) return kCodeUnknown;
  if (map.hasClasses()) return map.classes[map.index(x, y)];
  switch (map.occupancyAt(x, y)) {
    case Occupancy::kOccupied:
      return kCodeStatic;
    case Occupancy::kFree:
      return kCodeFree;
    case Occupancy::kUnknown:
      return kCodeUnknown;
  }
  return kCodeUnknown;
}

bool occupiedWithin(const GridMap& map, int x, int y, int tolerance) {
  for (int ny = y - tolerance; ny <= y + tolerance; ++ny) {
    for (int nx = x - tolerance; nx <= x + tolerance; ++nx) {
      if (map.contains(nx, ny) && map.occupancyAt(nx, ny) == Occupancy::kOccupied) return true;
    }
  }
  return false;
}

WallsKept measureWallsKept(const GridMap& rfm, const GridMap& plain, int tolerance) {
  const CellOffset plain_to_rfm = alignment(plain, rfm);
  WallsKept result;
  for (int y = 0; y < plain.height; ++y) {
    for (int x = 0; x < plain.width; ++x) {
      if (plain.occupancyAt(x, y) != Occupancy::kOccupied) continue;
      ++result.plain_occupied;
      const int rx = x + plain_to_rfm.dx, ry = y + plain_to_rfm.dy;
      if (occupiedWithin(rfm, rx, ry, tolerance)) {
        ++result.kept;
      } else {
        ++result.dropped_by_class[classAt(rfm, rx, ry)];
      }
    }
  }
  return result;
}

std::array<std::size_t, kClassCodes> countClasses(const GridMap& map) {
  std::array<std::size_t, kClassCodes> counts{};
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x)
      ++counts[classAt(map, x, y)];
  }
  return counts;
}

}  // namespace rfm::tools
