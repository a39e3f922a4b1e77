#pragma once

// Pictures of the measures on real recordings (ROS-free): the side-by-side picture of an RFM
// map and the plain grid of the same recording, and the people each map left.

#include "reflectance_field_map/render/image.h"
#include "reflectance_field_map/tools/grid_map_file.h"
#include "reflectance_field_map/tools/transient_evidence.h"

#include <cstddef>
#include <string>
#include <vector>

namespace rfm::tools {

// Colours of the plain grid's panel (the RFM's panel uses render::classColor).
render::Rgb plainOccupiedColor();        // occupied, kept by the RFM: black
render::Rgb droppedColor(uint8_t code);  // occupied, dropped by the RFM, by the RFM's class there

// RFM | plain grid over the union of both maps, `cells_per_pixel` cells a side in each pixel.
// A pixel shows the most telling cell of its block: in the RFM's panel glass and metal, then
// static, motion, free, unknown; in the plain grid's, a dropped cell, then occupied, free,
// unknown. The panels are 4 pixels apart.
render::RgbImage renderComparison(const GridMap& rfm, const GridMap& plain, int cells_per_pixel);

// Writes the picture at the finest scale that is at most `max_width` pixels wide and whose PNG
// takes at most `max_bytes`. Returns the cells per pixel used. Throws render::PngError.
int writeComparisonPicture(const std::string& path, const GridMap& rfm, const GridMap& plain,
                           int max_width, std::size_t max_bytes);

// The maps side by side over the union of their cells, `scale` pixels a cell: occupied cells
// black, or red where transient (people left), free near white, unknown grey.
render::Rgb transientColor();
render::RgbImage renderPeopleLeft(const std::vector<GridMap>& maps,
                                  const TransientEvidence& evidence, int scale);

}  // namespace rfm::tools
