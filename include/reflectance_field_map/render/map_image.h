#pragma once

#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/render/image.h"

namespace rfm {
namespace render {

// Colour of each class in map pictures (paper Fig. 1 style).
//   static       dark green      glass    blue        metal    red
//   motion       magenta         free     near white  unknown  grey
//   occupied     black (obstacle not classified by motion removal, e.g. the plain grid)
Rgb classColor(CellClass c);

// Draws `box` of the map, one pixel per cell enlarged `scale` times (>= 1), y up: the top
// row of the picture is the box's highest cell row. An empty box gives an empty picture.
RgbImage renderMap(const GlobalMap2D& map, const CellBox& box, int scale = 1);
// The whole explored map (map.bounds()).
RgbImage renderMap(const GlobalMap2D& map, int scale = 1);

// Scale that makes the longer side of a `box` picture about `target_pixels` long, within
// [1, max_scale].
int autoScale(const CellBox& box, int target_pixels = 1200, int max_scale = 4);

}  // namespace render
}  // namespace rfm
