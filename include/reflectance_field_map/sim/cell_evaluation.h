// Class metrics of a map against the simulator's world: for every map cell a true surface passes
// through, the class the map draws there (classes.pgm) against the surface's material, and for
// every cell drawn glass, metal or static, whether such a surface is there. ROS-free.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "reflectance_field_map/sim/world.h"

namespace rfm::sim {

// Class codes of classes.pgm (rfm_offline): one byte per map cell.
enum class MapClass : std::uint8_t {
  kUnknown = 0,
  kFree = 1,
  kStatic = 2,
  kGlass = 3,
  kMetal = 4,
  kMotion = 5,
};
constexpr int kMapClassCount = 6;
const char* mapClassName(MapClass map_class);

// A class map with its geometry. Cell (x, y) covers [origin + (x, y) * resolution, + resolution);
// y grows upwards (the picture's bottom row is y = 0).
struct ClassGrid {
  int width = 0, height = 0;
  double resolution = 0.05;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  std::vector<std::uint8_t> cells;  // row-major from y = 0
  std::uint8_t at(int x, int y) const {
    return cells[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x];
  }
};

// Parses a binary PGM (P5, maxval 255) of class codes, its rows top down. Throws
// std::runtime_error naming `source` for a malformed header, a size beyond 100000 cells a side,
// missing bytes or a code above 5.
ClassGrid parseClassPgm(const std::string& bytes, double resolution, const Eigen::Vector2d& origin,
                        const std::string& source);
// Reads DIR/classes.pgm with the resolution and origin of DIR/map.yaml.
ClassGrid readClassGrid(const std::string& directory);

// True materials of a map cell, as bits: the materials of every surface passing through it.
enum SurfaceBit : std::uint8_t {
  kDiffuseBit = 1,
  kGlassBit = 2,
  kMetalBit = 4,
  kMirrorBit = 8,
};
// One byte of SurfaceBits per cell of `grid`, from the world's segments and arcs.
std::vector<std::uint8_t> rasterizeSurfaces(const World& world, const ClassGrid& grid);
// `truth` (rasterizeSurfaces of `grid`) as a binary PGM in classes.pgm's layout: the same size,
// the top row the map's highest y, one byte of SurfaceBits per cell. For scripts that relate the
// true surfaces to the rays (scripts/unseen_glass.py).
std::string surfacesPgm(const ClassGrid& grid, const std::vector<std::uint8_t>& truth);

// Truth rows of the cell table: cells holding one material, and cells holding several (a pane's
// frame beside its glass), which are counted but not scored.
enum class SurfaceRow { kWall = 0, kGlass, kMetal, kMirror, kMixed };
constexpr int kSurfaceRowCount = 5;
const char* surfaceRowName(SurfaceRow row);

class CellConfusion {
 public:
  // Compares `classes` with the true materials `truth` (rasterizeSurfaces of the same grid).
  // A true cell counts only when it or a cell within `tolerance` cells (Chebyshev) is observed
  // (not unknown); its drawn class is its true class if an obstacle of that class lies within the
  // tolerance, else its own class if that is an obstacle, else the commonest obstacle class within
  // the tolerance, else its own class. A cell drawn glass, metal or static is right when a true
  // cell of a material it stands for lies within the tolerance: glass for glass, metal for metal,
  // diffuse for static, and a mirror for glass or metal.
  static CellConfusion evaluate(const ClassGrid& classes, const std::vector<std::uint8_t>& truth,
                                int tolerance);

  void merge(const CellConfusion& other);

  std::uint64_t count(SurfaceRow row, MapClass drawn) const {
    return counts_[static_cast<int>(row)][static_cast<int>(drawn)];
  }
  std::uint64_t rowTotal(SurfaceRow row) const;
  std::uint64_t unobserved(SurfaceRow row) const { return unobserved_[static_cast<int>(row)]; }
  std::uint64_t drawn(MapClass drawn) const;       // cells drawn so (glass, metal or static)
  std::uint64_t drawnRight(MapClass drawn) const;  // ... with their material within tolerance

  // Percentages, or a negative number when undefined (nothing to divide by).
  double precision(MapClass drawn) const;
  double recall(MapClass drawn) const;  // over wall (static), glass or metal cells
  double wallsDrawnSpecular() const;    // wall cells drawn glass or metal
  double mirrorsDrawnSpecular() const;  // mirror cells drawn glass or metal

  // Markdown tables (no heading): the metrics, then the confusion of true rows and drawn classes.
  std::string toMarkdown() const;
  // The cells of one table row: glass, metal and static precision and recall, then walls drawn
  // glass or metal ("P | R | ..."; "-" where undefined). kSummaryColumnNames heads them.
  std::string summaryColumns() const;
  static const char* const kSummaryColumnNames;
  // A JSON object; fromJson reads it back (throws std::runtime_error on bad input).
  std::string toJson() const;
  static CellConfusion fromJson(const std::string& json_text);

  bool operator==(const CellConfusion& other) const;

 private:
  static int drawnIndex(MapClass drawn);  // glass 0, metal 1, static 2; -1 otherwise
  std::array<std::array<std::uint64_t, kMapClassCount>, kSurfaceRowCount> counts_{};
  std::array<std::uint64_t, kSurfaceRowCount> unobserved_{};
  std::array<std::uint64_t, 3> drawn_{}, drawn_right_{};
};

}  // namespace rfm::sim
