#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/reflectance_field.h"
#include "reflectance_field_map/render/image.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace rfm {
namespace render {

// Theta-resolved slice of the field (paper Fig. 2 and 3): one column per position along a
// region, one row per theta bin. A column may gather several cells (a rectangle seen along
// one axis): a bin is reflective when it is reflective in any of them.
struct ThetaSlice {
  enum class Bin : uint8_t {
    kOutside = 0,     // no cell of the column lies in the active region: nothing known
    kUnobserved = 1,  // prior (log-odds 0) in every cell of the column
    kMissed = 2,      // some cell missed (p < 0.5), none reflective
    kReflective = 3,  // some cell reflective (p > 0.5)
  };

  int columns = 0;
  int bins = 0;
  std::vector<Bin> states;              // [column * bins + bin]
  std::vector<CellClass> column_class;  // class shown for reflective bins of each column
  std::vector<CellIndex> column_cell;   // first cell of each column

  Bin at(int column, int bin) const {
    return states[static_cast<size_t>(column) * static_cast<size_t>(bins) +
                  static_cast<size_t>(bin)];
  }
  int reflectiveCount(int column) const;
  int outsideColumns() const;
};

// Cells crossed by the segment p0 -> p1 (metres, fixed frame), in order, one column each.
std::vector<std::vector<CellIndex>> segmentColumns(const GridGeometry& geometry,
                                                   const Eigen::Vector2d& p0,
                                                   const Eigen::Vector2d& p1);
// Cells of the axis-aligned rectangle spanned by two corners: one column per cell along its
// longer side, each column holding the cells across the shorter side.
std::vector<std::vector<CellIndex>> rectangleColumns(const GridGeometry& geometry,
                                                     const Eigen::Vector2d& corner0,
                                                     const Eigen::Vector2d& corner1);

// Reads the bins of `columns` from the field. `map`, when given, sets each column's class
// (the most significant class among its cells: glass, metal, static, occupied, motion, ...).
ThetaSlice sampleThetaSlice(const ReflectanceField& field,
                            const std::vector<std::vector<CellIndex>>& columns,
                            const GlobalMap2D* map = nullptr);

// Draws a slice: x along the region (left = first column), theta up (bin 0 at the bottom).
// Reflective bins take the colour of their column's class (black when it is unknown or free:
// reflective evidence the map did not keep), missed bins are white, unobserved light grey,
// columns outside the active region a darker grey. Each column is `column_px` wide, each
// bin `bin_px` tall.
RgbImage renderThetaSlice(const ThetaSlice& slice, int column_px = 4, int bin_px = 2);

}  // namespace render
}  // namespace rfm
