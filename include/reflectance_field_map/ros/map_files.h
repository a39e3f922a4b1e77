#pragma once

#include "reflectance_field_map/core/mapper.h"

#include <nav_msgs/OccupancyGrid.h>

#include <cstdint>
#include <string>

// Map files on disk, shared by the live node and the offline tool.
namespace rfm::ros_glue {

// map_server format: PREFIX.pgm (P5, 254 free, 0 occupied, 205 unknown, top row = highest y)
// and PREFIX.yaml (image, resolution, origin, negate 0, occupied_thresh 0.65,
// free_thresh 0.196). False with `error` set (naming the file and the reason) on failure.
bool writeMapServerFiles(const std::string& prefix, const nav_msgs::OccupancyGrid& grid,
                         std::string* error);

// PREFIX.rfm: the mapper's whole state (rfm::Mapper::save) in a checksummed envelope
// (rfm::writeStateFile), to resume with loadMapperState(). Every file is written beside its name
// and renamed into place when complete: a failed or interrupted save leaves the earlier file.
std::string stateFilePath(const std::string& prefix);
bool writeMapperState(const std::string& prefix, const rfm::Mapper& mapper, std::string* error);

// PREFIX.pgm + PREFIX.yaml of the mapper's explored map (in `frame`) and PREFIX.rfm.
bool saveMapFiles(const std::string& prefix, const rfm::Mapper& mapper, const std::string& frame,
                  std::string* error);

// The largest saved state loadMapperState reads (bytes).
constexpr uint64_t kMaxStateFileBytes = uint64_t{8} << 30;

// Resumes from PATH.rfm (PATH may name the .rfm file itself) once its envelope, size and
// checksum are verified. On failure the mapper is unchanged and `error` says why.
bool loadMapperState(const std::string& path, rfm::Mapper& mapper, std::string* error);

}  // namespace rfm::ros_glue
